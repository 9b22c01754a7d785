#pragma once

#include <array>
#include <cstdint>
#include <string>

#include "cambio/hal/camera.hpp"
#include "cambio/hal/image.hpp"
#include "cambio/perception/ssm_server.hpp"
#include "cambio/ros2/ros_time.hpp"
#include "cambio_msgs/msg/SsmRequest.h"
#include "cambio_msgs/msg/SsmSummary.h"
#include "sensor_msgs/msg/Image.h"

// The SSM's request and result as cambio_msgs, and camera images as sensor_msgs/Image, both ways:
// what crosses the network when perception runs on another host. Internal to cambio_ros2.

namespace cambio::ros2 {

constexpr std::size_t kMaxLevels = perception::Retina::kMaxLevels;

/// An outgoing cambio_msgs/SsmSummary and the arrays its sequences borrow (no allocation after
/// construction).
class SsmSummaryMessage {
 public:
  explicit SsmSummaryMessage(std::string frame_id);
  SsmSummaryMessage(const SsmSummaryMessage&) = delete;
  SsmSummaryMessage& operator=(const SsmSummaryMessage&) = delete;
  /// The message of `summary`, stamped `stamp` (the left image's exposure, as ROS time).
  const cambio_msgs_msg_dds__SsmSummary_& fill(const perception::SsmSummary& summary,
                                               RosTime stamp);

 private:
  std::string frame_id_;
  cambio_msgs_msg_dds__SsmSummary_ message_{};
  std::array<std::array<cambio_msgs_msg_dds__LevelGeometry_, kMaxLevels>, 2> geometry_{};
  std::array<std::array<cambio_msgs_msg_dds__Moments_, kMaxLevels>, 2> moments_{};
  std::array<cambio_msgs_msg_dds__LevelDisparity_, kMaxLevels> disparity_levels_{};
  std::array<std::array<cambio_msgs_msg_dds__LevelMotion_, kMaxLevels>, 2> motion_levels_{};
};

/// A received summary, checked: "" and `out` filled (its stamp on the run's clock through
/// `epoch_offset_ns`, its sequence left to the caller), or what is wrong with it (a level count
/// beyond the retina's, per-level arrays longer than the levels, a disparity, flow or confidence
/// that is not a finite number in range).
std::string summary_from_message(const cambio_msgs_msg_dds__SsmSummary_& message,
                                 std::int64_t epoch_offset_ns, perception::SsmSummary& out);

/// The message of a request, stamped `stamp`.
cambio_msgs_msg_dds__SsmRequest_ request_message(const perception::SsmRequest& request,
                                                 RosTime stamp);
/// A received request, checked against the images' size (a fixation at most one image size
/// outside the image): "" and `out` filled, or what is wrong with it.
std::string request_from_message(const cambio_msgs_msg_dds__SsmRequest_& message,
                                 const hal::CameraIntrinsics& image, perception::SsmRequest& out);

/// The sensor_msgs/Image of `image` (mono8 or rgb8), stamped `stamp`, in frame `frame_id`: it
/// borrows the pixels and the frame id until written.
sensor_msgs_msg_dds__Image_ image_message(const hal::Image& image, const std::string& frame_id,
                                          RosTime stamp);

/// A received sensor_msgs/Image, checked against the camera it should come from (size, an
/// encoding of its pixel format: mono8 or rgb8, step, data length): "" and the pixels copied
/// into `out` (already sized for that camera: no allocation), its stamp on the run's clock, or
/// what is wrong with it.
std::string image_from_message(const sensor_msgs_msg_dds__Image_& message,
                               const hal::CameraInfo& camera, std::int64_t epoch_offset_ns,
                               hal::Image& out);

}  // namespace cambio::ros2
