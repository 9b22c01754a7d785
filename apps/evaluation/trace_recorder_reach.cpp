// The TraceRecorder's arm steps: the reaching arm's gripper in each row, and the newest reach
// (Trace::reach) against the ground truth.

#include <cmath>
#include <string>

#include "trace_recorder.hpp"
#include "true_gaze.hpp"

namespace cambio::app {

void TraceRecorder::record_arms(TraceRow& row, const sim::RayHit& dominant_hit) {
  note_refusal();
  const int side = reaching_arm();
  if (side < 0) return;
  const control::ArmStatus::Arm& arm = arm_status_.arms[static_cast<std::size_t>(side)];
  const control::ArmChain& chain = *sources_.arm_chains[static_cast<std::size_t>(side)];
  row.reach_arm = side;
  row.reach_phase = arm.phase;
  row.gripper_W_m = arm.gripper_W_m;
  row.gripper_distance_m = arm.distance_to_target_m;
  record_true_gripper(row, chain);
  if (arm.command_ns != last_reach_command_ns_) start_reach(side, arm, dominant_hit);
  if (arm.touch_ns != 0 && std::isnan(trace_.reach.touch_s)) record_touch(arm, chain);
  trace_.reach.final_phase = arm.phase;
}

void TraceRecorder::note_refusal() {
  ReachRecord& reach = trace_.reach;
  for (const control::ArmStatus::Arm& arm : arm_status_.arms) {
    if (arm.phase == control::ReachPhase::kRefused && !arm_status_.refusal().empty()) {
      reach.refused = true;
      reach.refusal = std::string(arm_status_.refusal());
    }
  }
}

/// The arm with a chain whose reach was accepted last (-1: none).
int TraceRecorder::reaching_arm() const {
  int side = -1;
  std::int64_t newest_ns = 0;
  for (int s = 0; s < 2; ++s) {
    const control::ArmStatus::Arm& arm = arm_status_.arms[static_cast<std::size_t>(s)];
    if (sources_.arm_chains[static_cast<std::size_t>(s)] && arm.command_ns > newest_ns) {
      side = s;
      newest_ns = arm.command_ns;
    }
  }
  return side;
}

void TraceRecorder::record_true_gripper(TraceRow& row, const control::ArmChain& chain) {
  sim::GroundTruth& truth = *sources_.truth;
  const double opening_rad = truth.joint_position_rad(chain.names[4]);
  const Eigen::Vector3d tip_W =
      truth.X_WL(chain.names[3]) * Eigen::Vector3d(chain.hand_m(opening_rad), 0, 0);
  row.true_gripper_W_m = detail::to_array(tip_W);
  if (!sources_.target_object.empty()) {
    row.true_gripper_surface_m = truth.distance_to_object_m(sources_.target_object, tip_W);
  }
}

void TraceRecorder::start_reach(int side, const control::ArmStatus::Arm& arm,
                                const sim::RayHit& dominant_hit) {
  // A new reach: the stereo estimate it took against where the dominant eye truly looked. The
  // refusal stays: it is the last one, whichever reach it refused.
  ReachRecord& reach = trace_.reach;
  last_reach_command_ns_ = arm.command_ns;
  const bool refused = reach.refused;
  const std::string refusal = reach.refusal;
  reach = ReachRecord{};
  reach.refused = refused;
  reach.refusal = refusal;
  reach.accepted = true;
  reach.arm = side;
  reach.command_s = static_cast<double>(arm.command_ns - start_ns_) * 1e-9;
  reach.estimate_W_m = arm.target_W_m;
  const bool named = !sources_.target_object.empty();
  if (dominant_hit.hit && (!named || dominant_hit.object == sources_.target_object)) {
    reach.true_target_W_m = detail::to_array(dominant_hit.p_W);
    reach.estimated_target_error_m = (detail::to_vector(arm.target_W_m) - dominant_hit.p_W).norm();
  }
}

void TraceRecorder::record_touch(const control::ArmStatus::Arm& arm,
                                 const control::ArmChain& chain) {
  ReachRecord& reach = trace_.reach;
  reach.touch_s = static_cast<double>(arm.touch_ns - start_ns_) * 1e-9;
  if (!sources_.target_object.empty()) {
    reach.touch_position_error_m =
        std::abs(sources_.truth->end_effector_gap_m(chain.names[4], sources_.target_object));
  }
}

}  // namespace cambio::app
