#include "console_session.hpp"

#include "console_session_detail.hpp"
#include "run_trace.hpp"

namespace cambio::app {
namespace {

using console::detail::degrees;
using console::detail::format;

// The gaze loop's action, vergence, disparity and believed fixation, once it has published.
void print_gaze_status(std::ostream& out, const control::GazeLoop& gaze_loop) {
  control::GazeStatus gaze;
  if (!gaze_loop.status().read(gaze) || !(gaze.stamp_ns > 0)) return;
  out << format(
      "gaze: %s%s, vergence %.2f deg, disparity %s, image error %.1f px, rejected %llu\n",
      gaze_action_name(gaze.action), gaze.saccade_active ? " (saccade under way)" : "",
      degrees(gaze.vergence_rad),
      gaze.disparity_valid
          ? format("%.2f px (confidence %.2f)", gaze.disparity_px, gaze.disparity_confidence)
                .c_str()
          : "invalid",
      gaze.feature_error_px, static_cast<unsigned long long>(gaze_loop.rejected_commands()));
  if (gaze.believed_fixation_valid) {
    const auto& p = gaze.believed_fixation_W_m;
    out << format("believed fixation (stereo): (%.3f, %.3f, %.3f) m\n", p[0], p[1], p[2]);
  } else {
    out << "believed fixation (stereo): none (the eyes' axes do not meet)\n";
  }
}

// Each arm's phase and gripper, once the arm loop has published.
void print_arm_status(std::ostream& out, const hal::SeqlockChannel<control::ArmStatus>& channel) {
  control::ArmStatus arms;
  if (!channel.read(arms) || !(arms.stamp_ns > 0)) return;
  for (int side = 0; side < 2; ++side) {
    const control::ArmStatus::Arm& arm = arms.arms[static_cast<std::size_t>(side)];
    const auto& g = arm.gripper_W_m;
    out << format("%s arm: %s, gripper %s at (%.3f, %.3f, %.3f) m", side == 0 ? "left" : "right",
                  reach_phase_name(arm.phase), arm.gripper_closed ? "closed" : "open", g[0], g[1],
                  g[2]);
    // Only a reach under way or done has a target to be far from.
    if (arm.phase == control::ReachPhase::kReaching ||
        arm.phase == control::ReachPhase::kTouching || arm.phase == control::ReachPhase::kArrived) {
      out << format(", %.3f m from its target", arm.distance_to_target_m);
    }
    out << "\n";
  }
}

}  // namespace

void ConsoleSession::print_status(std::int64_t now_ns) {
  out_ << format("t %.3f s\n", static_cast<double>(now_ns) * 1e-9);
  if (const control::GazeLoop* gaze_loop = job_.gaze_loop()) print_gaze_status(out_, *gaze_loop);
  if (const auto* arm_status = job_.arm_status()) print_arm_status(out_, *arm_status);
  // The joints as the loops believe them, beside the simulator's truth where there is one.
  const bool reported = believed_.read(q_believed_rig_);
  sim::GroundTruth* truth = job_.ground_truth();
  out_ << format("%-22s %12s %12s\n", "joint", "believed", truth != nullptr ? "true" : "");
  for (std::size_t i = 0; i < q_believed_rig_.size(); ++i) {
    const std::string& name = job_.joint_order()[i];
    std::string true_text;
    if (truth != nullptr) true_text = format("%8.3f deg", degrees(truth->joint_position_rad(name)));
    out_ << format("%-22s %8.3f deg %12s\n", name.c_str(), degrees(q_believed_rig_[i]),
                   true_text.c_str());
  }
  if (!reported) out_ << "(some joints have not reported yet)\n";
  if (believed_.holding()) out_ << "a joint loop HOLDS: a fault is latched or feedback is stale\n";
}

}  // namespace cambio::app
