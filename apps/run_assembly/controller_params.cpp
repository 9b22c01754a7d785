#include "controller_params.hpp"

#include <stdexcept>

namespace cambio::app {

namespace {

const config::LoopConfig& find_loop(const config::RigConfig& rig, const std::string& name) {
  const config::LoopConfig* loop = rig.find_loop(name);
  if (loop == nullptr) throw std::runtime_error("the rig defines no '" + name + "' loop");
  return *loop;
}

}  // namespace

runtime::LoopSchedule schedule_of(const config::LoopConfig& loop) {
  return {loop.rate_hz, loop.priority, loop.cpu,
          loop.overrun == config::OverrunPolicy::kCatchUp ? runtime::OverrunPolicy::kCatchUp
                                                          : runtime::OverrunPolicy::kSkip};
}

runtime::LoopSchedule loop_schedule(const config::RigConfig& rig, const std::string& loop_name) {
  return schedule_of(find_loop(rig, loop_name));
}

control::JointLoopParams joint_loop_params(const config::RigConfig& rig) {
  const config::LoopConfig& joint = find_loop(rig, "joint");
  control::JointLoopParams params;
  params.command_timeout_s = joint.command_timeout_s;
  params.feedback_timeout_s = joint.feedback_timeout_s;
  return params;
}

namespace {

control::GazeTarget gaze_target(const config::GazeTargetConfig& target) {
  control::GazeTarget out;
  switch (target.kind) {
    case config::GazeTargetKind::kNone:
      out.kind = control::GazeTargetKind::kNone;
      break;
    case config::GazeTargetKind::kPoint:
      out.kind = control::GazeTargetKind::kPoint;
      break;
    case config::GazeTargetKind::kPixel:
      out.kind = control::GazeTargetKind::kPixel;
      break;
    case config::GazeTargetKind::kAngles:
      out.kind = control::GazeTargetKind::kAngles;
      break;
  }
  out.point_W_m = target.point_W_m;
  out.pixel_px = target.pixel_px;
  out.angles_rad = target.angles_rad;
  return out;
}

}  // namespace

control::GazeAction gaze_action(config::GazeAction action) {
  switch (action) {
    case config::GazeAction::kHold:
      return control::GazeAction::kHold;
    case config::GazeAction::kFixate:
      return control::GazeAction::kFixate;
    case config::GazeAction::kSaccade:
      return control::GazeAction::kSaccade;
    case config::GazeAction::kPursue:
      return control::GazeAction::kPursue;
  }
  return control::GazeAction::kHold;
}

std::vector<double> max_tracking_errors_rad(const config::RigConfig& rig,
                                            const hal::HardwareInfo& hardware) {
  std::vector<double> limits;
  for (const auto& joint : hardware.joints) {
    const config::JointConfig* config = rig.find_joint(joint.name);
    if (config == nullptr) {
      throw std::runtime_error("the rig describes no joint '" + joint.name + "'");
    }
    limits.push_back(config->max_tracking_error_rad);
  }
  return limits;
}

control::GazeLoopParams gaze_loop_params(const config::ExperimentConfig& experiment,
                                         const hal::HardwareInfo& hardware) {
  if (!hardware.stereo) throw std::runtime_error("the gaze task needs a stereo rig");
  const config::GazeTaskConfig& gaze = experiment.gaze;
  const hal::Eye verging_eye = hal::other(gaze.dominant_eye);
  const hal::CameraInfo* verging =
      hardware.find_camera(verging_eye == hal::Eye::kRight ? hardware.stereo->right_camera
                                                           : hardware.stereo->left_camera);
  if (verging == nullptr) throw std::runtime_error("the stereo pair names an unknown camera");
  control::GazeLoopParams params;
  params.fixation.dominant_eye = gaze.dominant_eye;
  params.fixation.gain_per_s = gaze.fixation_gain_per_s;
  params.fixation.neck_rule_rad = gaze.neck_rule_rad;
  params.fixation.default_depth_m = gaze.default_depth_m;
  params.vergence.verging_eye = verging_eye;
  params.vergence.focal_px = verging->intrinsics.focal_x_px;
  params.vergence.gain = gaze.vergence.gain;
  params.vergence.min_confidence = gaze.vergence.min_confidence;
  params.vergence.max_step_rad = gaze.vergence.max_step_rad;
  params.vergence_enabled = gaze.vergence.enabled;
  params.predictive_vergence = gaze.saccade.predictive_vergence;
  params.pursuit_gain_per_s = gaze.pursuit.position_gain_per_s;
  params.pursuit_lead = gaze.pursuit.velocity_gain;
  params.max_tracking_error_rad = max_tracking_errors_rad(experiment.rig, hardware);
  return params;
}

control::ArmReachParams arm_reach_params(const config::ExperimentConfig& experiment,
                                         const hal::HardwareInfo& hardware,
                                         std::array<std::string, 2> groups) {
  const config::ArmTaskConfig& arm = experiment.arm;
  control::ArmReachParams params;
  params.groups = std::move(groups);
  params.gain_per_s = arm.gain_per_s;
  params.max_speed_m_s = arm.max_speed_m_s;
  params.max_acceleration_m_s2 = arm.max_acceleration_m_s2;
  params.probe_depth_m = arm.probe_depth_m;
  params.approach_m = arm.approach_m;
  params.arrive_tolerance_m = arm.arrive_tolerance_m;
  params.posture_gain_per_s = arm.posture_gain_per_s;
  params.gripper_speed_rad_s = arm.gripper_speed_rad_s;
  params.max_tracking_error_rad = max_tracking_errors_rad(experiment.rig, hardware);
  return params;
}

namespace {

control::ArmSide arm_side(config::ArmSideConfig side) {
  switch (side) {
    case config::ArmSideConfig::kLeft:
      return control::ArmSide::kLeft;
    case config::ArmSideConfig::kRight:
      return control::ArmSide::kRight;
    case config::ArmSideConfig::kNearest:
      break;
  }
  return control::ArmSide::kNearest;
}

control::ArmCommand arm_command(const config::ArmCommandConfig& config) {
  control::ArmCommand command;
  command.arm = arm_side(config.arm);
  switch (config.action) {
    case config::ArmActionConfig::kReach:
      command.action = control::ArmAction::kReach;
      command.target = config.to_fixation ? control::ReachTargetKind::kFixation
                                          : control::ReachTargetKind::kPoint;
      command.point_W_m = config.point_W_m;
      break;
    case config::ArmActionConfig::kGrasp:
      command.action = control::ArmAction::kGrasp;
      break;
    case config::ArmActionConfig::kRelease:
      command.action = control::ArmAction::kRelease;
      break;
  }
  return command;
}

}  // namespace

std::vector<control::CommandScript::Entry> command_script(
    const config::ExperimentConfig& experiment) {
  std::vector<control::CommandScript::Entry> entries;
  for (const auto& command : experiment.commands) {
    control::CommandScript::Entry entry;
    entry.at_s = command.at_s;
    if (command.arm) {
      entry.to_arms = true;
      entry.arm_command = arm_command(*command.arm);
      entries.push_back(entry);
      continue;
    }
    entry.command.action = gaze_action(command.action);
    entry.command.target = gaze_target(command.target);
    entry.command.verge = command.verge;
    entries.push_back(entry);
  }
  return entries;
}

}  // namespace cambio::app
