#include "camera_loop.hpp"

namespace cambio::app {

CameraLoop::CameraLoop(std::vector<hal::Camera*> cameras) : cameras_(std::move(cameras)) {
  for (const hal::Camera* camera : cameras_) {
    const auto& info = camera->info();
    channels_.push_back(std::make_unique<hal::TripleBuffer<hal::Image>>(
        hal::Image(info.intrinsics.width_px, info.intrinsics.height_px, info.format)));
  }
}

void CameraLoop::configure() {
  // Warm-up grab, not published: a backend's first frame builds contexts, compiles shaders or
  // maps buffers (heap work that must not land in the first update()).
  for (std::size_t i = 0; i < cameras_.size(); ++i) {
    hal::Image scratch = channels_[i]->back();
    (void)cameras_[i]->grab(scratch);
  }
}

hal::Status CameraLoop::update(const hal::LoopTick&) noexcept {
  hal::Status result = hal::Status::kOk;
  for (std::size_t i = 0; i < cameras_.size(); ++i) {
    const hal::Status status = cameras_[i]->grab(channels_[i]->back());
    if (status == hal::Status::kOk) {
      channels_[i]->publish();
      ++frames_grabbed_;
    } else if (status != hal::Status::kNoNewData) {
      result = status;
    }
  }
  return result;
}

}  // namespace cambio::app
