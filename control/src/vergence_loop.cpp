#include "cambio/control/vergence_loop.hpp"

#include <stdexcept>

namespace cambio::control {

VergenceLoop::VergenceLoop(const VergenceController& controller, const JointTargetFrame& pose,
                           int verging_joint, int dominant_joint,
                           const hal::SeqlockChannel<perception::SsmSummary>& summaries,
                           hal::SeqlockChannel<JointTargetFrame>& targets)
    : controller_(controller),
      pose_(pose),
      verging_joint_(verging_joint),
      dominant_joint_(dominant_joint),
      summaries_(summaries),
      targets_(targets) {
  if (verging_joint < 0 || verging_joint >= pose.count || dominant_joint < 0 ||
      dominant_joint >= pose.count || verging_joint == dominant_joint) {
    throw std::invalid_argument("vergence loop: eye joint indices outside the pose");
  }
  current_.verging_target_rad = pose_.commands[static_cast<std::size_t>(verging_joint)].value;
  status_.write(current_);
}

hal::Status VergenceLoop::update(const hal::LoopTick& tick) noexcept {
  (void)summaries_.read(summary_);  // A torn read keeps the last clean summary.
  const perception::SsmSummary& summary = summary_;
  if (summary.sequence != 0 && summary.sequence != last_sequence_) {
    last_sequence_ = summary.sequence;
    const DisparityMeasurement measurement{summary.disparity.valid,
                                           static_cast<double>(summary.disparity.disparity_px),
                                           static_cast<double>(summary.disparity.confidence)};
    auto& verging = pose_.commands[static_cast<std::size_t>(verging_joint_)];
    const double before = verging.value;
    verging.value = controller_.next_target_rad(
        before, pose_.commands[static_cast<std::size_t>(dominant_joint_)].value, measurement);
    ++current_.measurements;
    if (verging.value != before) ++current_.corrections;
    current_.disparity_px = measurement.disparity_px;
    current_.confidence = measurement.confidence;
    current_.valid = measurement.valid;
    current_.verging_target_rad = verging.value;
    status_.write(current_);
  }
  pose_.stamp_ns = tick.now_ns;
  targets_.write(pose_);
  return hal::Status::kOk;
}

}  // namespace cambio::control
