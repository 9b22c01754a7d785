#pragma once

#include <string>

#include "cambio/control/joint_frames.hpp"
#include "cambio/hal/loop.hpp"
#include "cambio/hal/seqlock_channel.hpp"

namespace cambio::control {

/// The control loop of a task that holds a pose: it republishes the same targets every cycle,
/// stamped, so the joint loop's limits, ramps and watchdog act as they would under any
/// controller. Real-time safe.
class PoseHoldLoop final : public hal::Loop {
 public:
  PoseHoldLoop(const JointTargetFrame& pose, hal::SeqlockChannel<JointTargetFrame>& targets)
      : pose_(pose), targets_(targets) {}

  const std::string& name() const override { return name_; }
  hal::Status update(const hal::LoopTick& tick) noexcept override {
    pose_.stamp_ns = tick.now_ns;
    targets_.write(pose_);
    return hal::Status::kOk;
  }

 private:
  std::string name_ = "control";
  JointTargetFrame pose_;
  hal::SeqlockChannel<JointTargetFrame>& targets_;
};

}  // namespace cambio::control
