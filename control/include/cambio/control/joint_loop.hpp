#pragma once

#include <string>
#include <vector>

#include "cambio/control/joint_frames.hpp"
#include "cambio/hal/joint_group.hpp"
#include "cambio/hal/loop.hpp"
#include "cambio/hal/seqlock_channel.hpp"

namespace cambio::control {

/// The fast loop next to the hardware (1 kHz by default). Each cycle it reads every joint group,
/// publishes the states, and sends the newest targets after enforcing, per joint:
///  - position limits (the target is clamped, never sent beyond a limit; a NaN or infinite
///    target holds the joint still),
///  - the velocity limit (a position target moves at most max_velocity * period per cycle, so a
///    step from the control loop becomes a ramp),
///  - a watchdog: targets older than `command_timeout_s` are stale; the joints then hold the
///    last measured position (velocity commands drop to zero) until fresh targets arrive.
/// Joint order is the concatenation of the groups' joint lists.
class JointLoop final : public hal::Loop {
 public:
  JointLoop(std::vector<hal::JointGroup*> groups, hal::SeqlockChannel<JointTargetFrame>& targets,
            hal::SeqlockChannel<JointStateFrame>& states, double command_timeout_s);

  const std::string& name() const override { return name_; }
  /// Checks the joint count fits kMaxJoints; sizes the scratch buffers. Throws on a bad setup.
  void configure() override;
  /// Reads once so the first targets hold the current pose.
  void activate() override;
  hal::Status update(const hal::LoopTick& tick) noexcept override;

  int joint_count() const { return joint_count_; }
  /// Cycles in which the watchdog held the joints because targets were stale.
  std::uint64_t stale_cycles() const { return stale_cycles_; }

 private:
  std::string name_ = "joint";
  std::vector<hal::JointGroup*> groups_;
  hal::SeqlockChannel<JointTargetFrame>& targets_;
  hal::SeqlockChannel<JointStateFrame>& states_;
  double command_timeout_s_;
  int joint_count_ = 0;
  std::vector<hal::JointLimits> limits_;
  std::vector<hal::JointState> state_scratch_;
  std::vector<hal::JointCommand> command_scratch_;
  std::vector<double> last_position_target_;  // What was sent last cycle, for the rate limit.
  JointStateFrame state_frame_{};
  std::uint64_t stale_cycles_ = 0;
};

}  // namespace cambio::control
