#pragma once

// What the ROS 2 bridge says of the run besides the joints: /diagnostics (each loop's rate,
// jitter and overruns; each joint loop's holds; each drive's CiA 402 state, error code and status
// bits; each CAN group's counters and homing) and the gaze (/cambio/gaze/*). The samplers run on
// the bridge's own threads and read only what is safe while the loops run: latest-value
// channels, atomics, the executors' live counters.

#include <string>
#include <vector>

#include "cambio/canopen/can_joint_group.hpp"
#include "cambio/control/gaze_loop.hpp"
#include "cambio/control/joint_loop.hpp"
#include "cambio/hal/seqlock_channel.hpp"
#include "cambio/ros2/perception_link.hpp"
#include "cambio/ros2/ros2_bridge.hpp"
#include "cambio/runtime/executor.hpp"

namespace cambio::app {

struct DiagnosticsInputs {
  struct JointLoopView {
    const control::JointLoop* loop = nullptr;
    const hal::SeqlockChannel<control::JointStateFrame>* states = nullptr;
    std::vector<int> rig_indices;  ///< Where its joints sit in rig order.
  };
  runtime::Executor* executor = nullptr;  ///< Its clock stamps the array; its loops are listed.
  std::vector<JointLoopView> joint_loops;
  std::vector<std::string> joint_names;   ///< Rig order.
  std::vector<std::string> joint_groups;  ///< Each rig joint's group.
  std::vector<const canopen::CanJointGroup*> can_groups;
  /// With perception on another host: the link's state (ERROR while it is lost).
  const ros2::RobotPerceptionLink* perception_link = nullptr;
};

/// /diagnostics: one status per loop, per joint loop's hold, per drive, per CAN group, and the
/// perception link when there is one.
ros2::DiagnosticsSampler make_diagnostics_sampler(DiagnosticsInputs inputs);

/// /cambio/gaze/fixation and /cambio/gaze/status from the gaze loop's status channel.
ros2::GazeSampler make_gaze_sampler(const control::GazeLoop& gaze_loop);

}  // namespace cambio::app
