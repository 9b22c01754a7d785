#pragma once

#include <string>
#include <vector>

#include "cambio/control/believed_joints.hpp"
#include "cambio/control/command_tracking.hpp"
#include "cambio/control/joint_frames.hpp"
#include "cambio/hal/hardware_info.hpp"
#include "cambio/hal/loop.hpp"
#include "cambio/hal/seqlock_channel.hpp"

namespace cambio::control {

/// The control loop of a task that holds a pose: it publishes the pose every cycle, stamped, so
/// the joint loop's limits, ramps and watchdog act as they would under any controller. Like every
/// controller it follows the drives (CommandTracking): frozen while a joint loop holds or a joint
/// is not driven; at its first cycle and after a hold it publishes the measured pose and goes to
/// the pose from there at each joint's velocity limit; a joint whose command leads its measurement
/// by more than its max_tracking_error_rad is a fault of this loop (reported, the joints held where
/// they are, kFault to the end of the run). Real-time safe after construction.
class PoseHoldLoop final : public hal::Loop {
 public:
  /// `pose`: every rig joint's target, rig order (the groups' joints concatenated).
  /// `max_tracking_error_rad`: one per hardware.joints entry; empty: unbounded. Throws
  /// std::invalid_argument for a pose or believed joints that are not the rig's.
  PoseHoldLoop(const hal::HardwareInfo& hardware, const JointTargetFrame& pose,
               BelievedJoints believed, const std::vector<double>& max_tracking_error_rad,
               hal::SeqlockChannel<JointTargetFrame>& targets);

  const std::string& name() const override { return name_; }
  hal::Status update(const hal::LoopTick& tick) noexcept override;
  const CommandTracking& tracking() const { return tracking_; }

 private:
  void write(std::int64_t now_ns) noexcept;

  std::string name_ = "control";
  JointTargetFrame pose_;                   // What is held, rig order.
  std::vector<double> q_command_rig_;       // What is commanded, rig order.
  std::vector<double> q_measured_rig_;      // Encoders, rig order.
  std::vector<double> max_velocity_rad_s_;  // Rig order.
  BelievedJoints believed_;
  CommandTracking tracking_;
  JointTargetFrame frame_;
  hal::SeqlockChannel<JointTargetFrame>& targets_;
  bool started_ = false;  // The command has been set to a measured pose once.
};

}  // namespace cambio::control
