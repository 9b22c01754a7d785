#include "cambio/perception/ssm_server.hpp"

#include <stdexcept>
#include <utility>

namespace cambio::perception {

SsmServer::SsmServer(std::string name, hal::TripleBuffer<hal::StereoFrame>& pairs,
                     const hal::CameraInfo& left, const hal::CameraInfo& right, SsmConfig config)
    : name_(std::move(name)),
      pairs_(pairs),
      left_info_(left),
      right_info_(right),
      config_(std::move(config)) {}

SsmServer::~SsmServer() = default;

void SsmServer::configure() {
  const hal::CameraInfo& left = left_info_;
  const hal::CameraInfo& right = right_info_;
  if (left.intrinsics.width_px != right.intrinsics.width_px ||
      left.intrinsics.height_px != right.intrinsics.height_px) {
    throw std::invalid_argument("SSM '" + name_ + "': cameras '" + left.name + "' and '" +
                                right.name + "' differ in size");
  }
  if (!(left.rate_hz > 0.0)) {
    throw std::invalid_argument("SSM '" + name_ + "': camera '" + left.name +
                                "' has no positive rate");
  }
  max_stamp_skew_ns_ = static_cast<std::int64_t>(0.5e9 / left.rate_hz);
  servo_ =
      std::make_unique<SensoryServo>(config_, left.intrinsics.width_px, left.intrinsics.height_px);
  // Real lenses are not pinholes: the retinas read each camera's ideal image through its model.
  servo_->set_lenses(LensDistortion(left.intrinsics, left.distortion),
                     LensDistortion(right.intrinsics, right.distortion));
  frames_ = std::make_unique<hal::TripleBuffer<SsmFrame>>(servo_->make_frame());
}

void SsmServer::activate() {
  if (servo_) servo_->reset_motion();
}

hal::Status SsmServer::update(const hal::LoopTick& /*tick*/) noexcept {
  if (!servo_) return hal::Status::kRejected;
  if (!pairs_.acquire()) return hal::Status::kNoNewData;
  const hal::StereoFrame& pair = pairs_.front();
  if (!pair.complete()) return hal::Status::kNoNewData;
  const auto matches = [](const hal::Image& image, const hal::CameraInfo& info) {
    return image.width_px == info.intrinsics.width_px &&
           image.height_px == info.intrinsics.height_px && image.format == info.format;
  };
  if (!matches(pair.left, left_info_) || !matches(pair.right, right_info_)) {
    return hal::Status::kRejected;
  }
  if (pair.stamp_skew_ns() > max_stamp_skew_ns_) {
    ++mismatched_pairs_;
    return hal::Status::kRejected;
  }

  (void)requests_.read(request_);
  std::array<PixelPoint, 2> fixation = request_.fixation;
  if (!request_.fixation_set) {
    fixation[0] = {pair.left.width_px / 2, pair.left.height_px / 2};
    fixation[1] = {pair.right.width_px / 2, pair.right.height_px / 2};
  }
  SsmFrame& frame = frames_->back();
  const hal::Status status =
      servo_->process(pair.left, pair.right, fixation[0], fixation[1], request_.features, frame);
  if (status != hal::Status::kOk) return status;
  frames_->publish();
  summaries_.write(frame.summary);
  return hal::Status::kOk;
}

}  // namespace cambio::perception
