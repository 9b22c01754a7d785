#include "cambio/perception/camera_loop.hpp"

#include <algorithm>
#include <stdexcept>

namespace cambio::perception {

namespace {

hal::Image image_for(const hal::Camera& camera) {
  const auto& info = camera.info();
  return hal::Image(info.intrinsics.width_px, info.intrinsics.height_px, info.format);
}

}  // namespace

CameraLoop::CameraLoop(std::vector<hal::Camera*> cameras, std::optional<StereoPairIndices> stereo)
    : cameras_(std::move(cameras)), stereo_(stereo) {
  for (const hal::Camera* camera : cameras_) {
    if (camera == nullptr) throw std::invalid_argument("camera loop: null camera");
  }
  if (stereo_) {
    if (stereo_->left >= cameras_.size() || stereo_->right >= cameras_.size() ||
        stereo_->left == stereo_->right) {
      throw std::invalid_argument("camera loop: the stereo pair must name two different cameras");
    }
    stereo_channel_ = std::make_unique<hal::TripleBuffer<hal::StereoFrame>>(hal::StereoFrame{
        image_for(*cameras_[stereo_->left]), image_for(*cameras_[stereo_->right])});
  }
  for (std::size_t i = 0; i < cameras_.size(); ++i) {
    const bool in_pair = stereo_ && (i == stereo_->left || i == stereo_->right);
    channels_.push_back(
        in_pair ? nullptr
                : std::make_unique<hal::TripleBuffer<hal::Image>>(image_for(*cameras_[i])));
  }
}

void CameraLoop::configure() {
  for (hal::Camera* camera : cameras_) {
    hal::Image scratch = image_for(*camera);
    (void)camera->grab(scratch);
  }
}

bool CameraLoop::allocates_in_update() const {
  return std::any_of(cameras_.begin(), cameras_.end(),
                     [](const hal::Camera* camera) { return camera->grab_allocates(); });
}

hal::Status CameraLoop::update(const hal::LoopTick&) noexcept {
  hal::Status result = hal::Status::kOk;
  auto note = [&](hal::Status status) {
    if (status == hal::Status::kOk) ++frames_grabbed_;
    if (status != hal::Status::kNoNewData) result = hal::worst(result, status);
  };
  if (stereo_) {
    hal::StereoFrame& pair = stereo_channel_->back();
    const hal::Status left = cameras_[stereo_->left]->grab(pair.left);
    const hal::Status right = cameras_[stereo_->right]->grab(pair.right);
    note(left);
    note(right);
    // An eye that delivered waits in the back slot for its partner (independent cameras need
    // not deliver in the same cycle); the consumer checks how far apart the stamps are.
    left_new_ = left_new_ || left == hal::Status::kOk;
    right_new_ = right_new_ || right == hal::Status::kOk;
    if (left_new_ && right_new_) {
      if (observed_stereo_channel_) {
        observed_stereo_channel_->back() = pair;
        observed_stereo_channel_->publish();
      }
      stereo_channel_->publish();
      ++pairs_published_;
      left_new_ = right_new_ = false;
    } else if (left_new_ || right_new_) {
      ++incomplete_pairs_;
    }
  }
  for (std::size_t i = 0; i < cameras_.size(); ++i) {
    if (!channels_[i]) continue;
    const hal::Status status = cameras_[i]->grab(channels_[i]->back());
    note(status);
    if (status == hal::Status::kOk) channels_[i]->publish();
  }
  return result;
}

hal::TripleBuffer<hal::Image>& CameraLoop::frames(std::size_t camera_index) {
  if (camera_index >= channels_.size() || !channels_[camera_index]) {
    throw std::out_of_range("camera loop: camera " + std::to_string(camera_index) +
                            " has no channel of its own (out of range or in the stereo pair)");
  }
  return *channels_[camera_index];
}

hal::TripleBuffer<hal::StereoFrame>& CameraLoop::stereo_frames() {
  if (!stereo_channel_) throw std::logic_error("camera loop: no stereo pair");
  return *stereo_channel_;
}

hal::TripleBuffer<hal::StereoFrame>& CameraLoop::observed_stereo_frames() {
  if (!stereo_channel_) throw std::logic_error("camera loop: no stereo pair");
  if (!observed_stereo_channel_) {
    observed_stereo_channel_ =
        std::make_unique<hal::TripleBuffer<hal::StereoFrame>>(stereo_channel_->front());
  }
  return *observed_stereo_channel_;
}

}  // namespace cambio::perception
