#pragma once

#include <string>

#include "cambio/control/joint_frames.hpp"
#include "cambio/control/vergence_controller.hpp"
#include "cambio/hal/loop.hpp"
#include "cambio/hal/seqlock_channel.hpp"
#include "cambio/perception/sensory_servo.hpp"

namespace cambio::control {

/// What the vergence loop has done so far (for progress reports and scoring).
struct VergenceStatus {
  std::uint64_t measurements = 0;  ///< New SSM summaries seen.
  std::uint64_t corrections = 0;   ///< Of those, confident enough to move the eye.
  double disparity_px = 0.0;       ///< The newest measurement.
  double confidence = 0.0;
  bool valid = false;
  double verging_target_rad = 0.0;
};

/// The control loop of the paper's vergence experiment: every joint holds its pose except the
/// verging eye, which the VergenceController moves once per new disparity measurement from the
/// Sensory Servo Module. Real-time safe after construction.
class VergenceLoop final : public hal::Loop {
 public:
  /// `pose` holds every joint's target (rig order); `verging_joint` and `dominant_joint` index
  /// into it.
  VergenceLoop(const VergenceController& controller, const JointTargetFrame& pose,
               int verging_joint, int dominant_joint,
               const hal::SeqlockChannel<perception::SsmSummary>& summaries,
               hal::SeqlockChannel<JointTargetFrame>& targets);

  const std::string& name() const override { return name_; }
  hal::Status update(const hal::LoopTick& tick) noexcept override;

  const hal::SeqlockChannel<VergenceStatus>& status() const { return status_; }

 private:
  std::string name_ = "control";
  VergenceController controller_;
  JointTargetFrame pose_;
  int verging_joint_;
  int dominant_joint_;
  const hal::SeqlockChannel<perception::SsmSummary>& summaries_;
  hal::SeqlockChannel<JointTargetFrame>& targets_;
  hal::SeqlockChannel<VergenceStatus> status_;
  VergenceStatus current_;
  perception::SsmSummary summary_{};
  std::uint64_t last_sequence_ = 0;
};

}  // namespace cambio::control
