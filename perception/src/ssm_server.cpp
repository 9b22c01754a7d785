#include "cambio/perception/ssm_server.hpp"

#include <stdexcept>
#include <utility>

namespace cambio::perception {

SsmServer::SsmServer(std::string name, hal::Camera& left, hal::Camera& right, SsmConfig config)
    : name_(std::move(name)),
      left_camera_(left),
      right_camera_(right),
      config_(std::move(config)) {}

SsmServer::~SsmServer() = default;

void SsmServer::configure() {
  const hal::CameraInfo& left = left_camera_.info();
  const hal::CameraInfo& right = right_camera_.info();
  if (left.intrinsics.width_px != right.intrinsics.width_px ||
      left.intrinsics.height_px != right.intrinsics.height_px) {
    throw std::invalid_argument("SSM '" + name_ + "': cameras '" + left.name + "' and '" +
                                right.name + "' differ in size");
  }
  left_image_.resize(left.intrinsics.width_px, left.intrinsics.height_px, left.format);
  right_image_.resize(right.intrinsics.width_px, right.intrinsics.height_px, right.format);
  servo_ =
      std::make_unique<SensoryServo>(config_, left.intrinsics.width_px, left.intrinsics.height_px);
  frames_ = std::make_unique<hal::TripleBuffer<SsmFrame>>(servo_->make_frame());
}

void SsmServer::activate() {
  if (servo_) servo_->reset_motion();
}

hal::Status SsmServer::update(const hal::LoopTick& /*tick*/) noexcept {
  if (!servo_) return hal::Status::kRejected;
  const hal::Status left = left_camera_.grab(left_image_);
  const hal::Status right = right_camera_.grab(right_image_);
  if (left == hal::Status::kNoNewData && right == hal::Status::kNoNewData) {
    return hal::Status::kNoNewData;
  }
  const auto usable = [](hal::Status status) {
    return status == hal::Status::kOk || status == hal::Status::kNoNewData;
  };
  if (!usable(left) || !usable(right)) return usable(left) ? right : left;
  if (left_image_.sequence == 0 || right_image_.sequence == 0) return hal::Status::kNoNewData;

  SsmRequest request;
  requests_.read(request);
  std::array<PixelPoint, 2> fixation = request.fixation;
  if (!request.fixation_set) {
    fixation[0] = {left_image_.width_px / 2, left_image_.height_px / 2};
    fixation[1] = {right_image_.width_px / 2, right_image_.height_px / 2};
  }
  SsmFrame& frame = frames_->back();
  const hal::Status status =
      servo_->process(left_image_, right_image_, fixation[0], fixation[1], request.features, frame);
  if (status != hal::Status::kOk) return status;
  frames_->publish();
  summaries_.write(frame.summary);
  return hal::Status::kOk;
}

}  // namespace cambio::perception
