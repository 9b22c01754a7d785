#include "cambio/control/arm_reach_loop.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <stdexcept>

#include "arm_reach_law.hpp"

namespace cambio::control {
namespace {

std::size_t at(int index) {
  return static_cast<std::size_t>(index);
}

/// Moves `q` toward `goal` by at most `step` (> 0).
double step_toward(double q, double goal, double step) {
  return q + std::clamp(goal - q, -step, step);
}

}  // namespace

ArmReachLoop::ArmReachLoop(const hal::HardwareInfo& hardware, const ArmReachParams& params,
                           const JointTargetFrame& pose, BelievedJoints believed,
                           const hal::SeqlockChannel<GazeStatus>* gaze,
                           const hal::SeqlockChannel<ArmCommand>& commands,
                           std::array<hal::TouchSensor*, 2> touch)
    : params_(params),
      command_kinematics_(hardware),
      believed_kinematics_(hardware),
      believed_(std::move(believed)),
      gaze_(gaze),
      commands_(commands),
      pose_(pose) {
  if (!(params.gain_per_s > 0.0) || !(params.max_speed_m_s > 0.0) ||
      !(params.max_acceleration_m_s2 > 0.0) || !(params.probe_depth_m >= 0.0) ||
      !(params.arrive_tolerance_m > 0.0) || !(params.approach_m >= 0.0) ||
      !(params.posture_gain_per_s >= 0.0) || !(params.gripper_speed_rad_s > 0.0) ||
      !(params.hand_pitches.step_rad > 0.0) || !(params.hand_pitches.max_deviation_rad >= 0.0)) {
    throw std::invalid_argument(
        "arm loop: gain, speed, acceleration, tolerance, gripper speed and pitch step must be > "
        "0, the probe depth, approach, posture gain and pitch range >= 0");
  }
  const int rig_count = command_kinematics_.rig_joint_count();
  if (pose.count != rig_count || believed_.rig_joint_count() != rig_count) {
    throw std::invalid_argument("arm loop: the pose and the believed joints must hold the rig's " +
                                std::to_string(rig_count) + " joints");
  }
  for (std::size_t side = 0; side < 2; ++side) {
    if (params.groups[side].empty()) continue;
    Arm& arm = arms_[side];
    arm.present = true;
    arm.chain = find_arm_chain(hardware, params.groups[side]);
    if (!arm.chain.has_touch_sensor) {
      throw std::invalid_argument("arm '" + params.groups[side] +
                                  "': no touch sensor on its gripper '" + arm.chain.names[4] +
                                  "': the reach stops on it and reaches with its fingertips "
                                  "(touch_sensors.<name>: {parent, fingertip_xy_m})");
    }
    arm.touch = touch[side];
    arm.wrist_frame = Kinematics::link_frame(arm.chain.joints[3]);
    arm_rig_indices_.insert(arm_rig_indices_.end(), arm.chain.rig.begin(), arm.chain.rig.end());
  }
  if (arm_rig_indices_.empty()) throw std::invalid_argument("arm loop: no arm group given");
  const auto& max_error = params.max_tracking_error_rad;
  if (!max_error.empty() && max_error.size() != hardware.joints.size()) {
    throw std::invalid_argument("arm loop: " + std::to_string(max_error.size()) +
                                " tracking error limits for " +
                                std::to_string(hardware.joints.size()) + " joints");
  }
  std::vector<CommandTracking::Joint> tracked;
  for (std::size_t side = 0; side < 2; ++side) {
    const Arm& arm = arms_[side];
    if (!arm.present) continue;
    for (std::size_t k = 0; k < 5; ++k) {
      CommandTracking::Joint joint;
      joint.name = arm.chain.names[k];
      joint.rig = arm.chain.rig[k];
      joint.index = arm.chain.joints[k];
      if (!max_error.empty()) joint.max_error_rad = max_error[at(joint.index)];
      if (k == 4) gripper_tracked_[side] = static_cast<int>(tracked.size());
      tracked.push_back(std::move(joint));
    }
  }
  tracking_ = CommandTracking(name_, std::move(tracked));
  law_ = std::make_unique<detail::ArmReachLaw>(params.gain_per_s);
  for (const auto& joint : hardware.joints) limits_tree_.push_back(joint.limits);
  rig_to_tree_.assign(command_kinematics_.rig_to_tree().begin(),
                      command_kinematics_.rig_to_tree().end());
  q_command_tree_.assign(at(command_kinematics_.joint_count()), 0.0);
  q_believed_rig_.assign(at(rig_count), 0.0);
  for (int i = 0; i < rig_count; ++i) {
    q_command_tree_[at(rig_to_tree_[at(i)])] = pose.commands[at(i)].value;
    q_believed_rig_[at(i)] = pose.commands[at(i)].value;
  }
  q_believed_tree_ = q_command_tree_;
  for (Arm& arm : arms_) {
    if (arm.present) arm.gripper_goal_rad = q_command_tree_[at(arm.chain.joints[4])];
  }
  J_W_ = command_kinematics_.make_jacobian();
  (void)command_kinematics_.update(q_command_tree_);
  (void)believed_kinematics_.update(q_believed_tree_);
}

ArmReachLoop::~ArmReachLoop() = default;

const ArmChain* ArmReachLoop::arm(int side) const {
  if (side < 0 || side > 1 || !arms_[at(side)].present) return nullptr;
  return &arms_[at(side)].chain;
}

hal::Status ArmReachLoop::update(const hal::LoopTick& tick) noexcept {
  const std::int64_t now_ns = tick.now_ns;
  const double dt_s = tick.period_s;
  (void)believed_.read(q_believed_rig_);
  for (std::size_t i = 0; i < q_believed_rig_.size(); ++i) {
    q_believed_tree_[at(rig_to_tree_[i])] = q_believed_rig_[i];
  }
  (void)believed_kinematics_.update(q_believed_tree_);
  const CommandTracking::Step tracking = tracking_.step(believed_);
  ArmCommand command;
  if (commands_.read(command) && command.sequence != 0 &&
      command.sequence != last_command_sequence_) {
    last_command_sequence_ = command.sequence;
    apply(command, now_ns);
  }
  if (trajectories_.take_new()) start_trajectory(now_ns);
  status_.joints_held = tracking == CommandTracking::Step::kFrozen;
  switch (tracking) {
    case CommandTracking::Step::kFollow:
      break;
    case CommandTracking::Step::kFrozen:
      // The drives do not follow: what is commanded stays as it was, so nothing winds up.
      publish(now_ns);
      return hal::Status::kOk;
    case CommandTracking::Step::kRestart:
      // The first command after a hold is where the joints are; motion resumes next cycle.
      restart_from_measured(now_ns);
      publish(now_ns);
      return hal::Status::kOk;
    case CommandTracking::Step::kFaulted:
      publish(now_ns);
      return hal::Status::kFault;
  }
  step_arms(now_ns, dt_s);
  if (follower_.active()) {
    // A gripper the trajectory moves keeps where it put it as its goal.
    std::array<bool, 2> grippers{};
    for (std::size_t side = 0; side < 2; ++side) {
      grippers[side] = arms_[side].present && follower_.drives(arms_[side].chain.joints[4]);
    }
    (void)follower_.step(now_ns, q_command_tree_);
    for (std::size_t side = 0; side < 2; ++side) {
      if (grippers[side])
        arms_[side].gripper_goal_rad = q_command_tree_[at(arms_[side].chain.joints[4])];
    }
  }
  for (std::size_t side = 0; side < 2; ++side) {
    if (gripper_tracked_[side] < 0) continue;
    // Closing, the fingers stop on what they hold while the command goes on: that lag is the
    // grasp, not a fault.
    const Arm& arm = arms_[side];
    tracking_.set_bounded(at(gripper_tracked_[side]),
                          arm.gripper_goal_rad > arm.chain.limits[4].min_position_rad);
  }
  if (tracking_.check(q_command_tree_, q_believed_tree_)) {
    stop_on_tracking_fault();
    publish(now_ns);
    return report_fault(tracking_.fault_message());
  }
  publish(now_ns);
  return hal::Status::kOk;
}

void ArmReachLoop::step_arms(std::int64_t now_ns, double dt_s) noexcept {
  for (int side = 0; side < 2; ++side) {
    Arm& arm = arms_[at(side)];
    if (!arm.present) continue;
    ArmStatus::Arm& s = status_.arms[at(side)];
    const int gripper = arm.chain.joints[4];
    double& opening = q_command_tree_[at(gripper)];
    opening = step_toward(opening, arm.gripper_goal_rad, params_.gripper_speed_rad_s * dt_s);
    if (arm.move_joint >= 0) {
      double& q = q_command_tree_[at(arm.move_joint)];
      q = step_toward(q, arm.move_goal_rad,
                      0.5 * limits_tree_[at(arm.move_joint)].max_velocity_rad_s * dt_s);
      if (q == arm.move_goal_rad) arm.move_joint = -1;
    }
    if (s.phase == ReachPhase::kReaching) reach_step(side, now_ns, dt_s);
  }
}

void ArmReachLoop::publish(std::int64_t now_ns) noexcept {
  for (int side = 0; side < 2; ++side) {
    const Arm& arm = arms_[at(side)];
    if (!arm.present) continue;
    ArmStatus::Arm& s = status_.arms[at(side)];
    const double opening = q_command_tree_[at(arm.chain.joints[4])];
    s.gripper_closed = arm.gripper_goal_rad <= arm.chain.limits[4].min_position_rad &&
                       opening <= arm.chain.limits[4].min_position_rad;
    const Eigen::Vector3d tip = tip_W(believed_kinematics_, arm);
    for (int i = 0; i < 3; ++i) s.gripper_W_m[at(i)] = tip[i];
    s.distance_to_target_m = s.command_ns != 0 ? (tip - arm.target_W).norm() : 0.0;
  }
  for (int i = 0; i < pose_.count; ++i) {
    pose_.commands[at(i)].value = q_command_tree_[at(rig_to_tree_[at(i)])];
  }
  pose_.stamp_ns = now_ns;
  targets_.write(pose_);
  status_.stamp_ns = now_ns;
  status_channel_.write(status_);
}

void ArmReachLoop::restart_from_measured(std::int64_t now_ns) noexcept {
  tracking_.restart(q_command_tree_, q_believed_tree_);
  follower_.stop();  // Its timing is gone: the arms hold where they are.
  for (Arm& arm : arms_) arm.ramp_from_ns = now_ns;
}

void ArmReachLoop::stop_on_tracking_fault() noexcept {
  tracking_.restart(q_command_tree_, q_believed_tree_);
  follower_.stop();
  for (int side = 0; side < 2; ++side) {
    Arm& arm = arms_[at(side)];
    if (!arm.present) continue;
    stop(side);
    arm.gripper_goal_rad = q_command_tree_[at(arm.chain.joints[4])];
  }
  status_.tracking_fault = true;
}

void ArmReachLoop::apply(const ArmCommand& command, std::int64_t now_ns) noexcept {
  if (tracking_.faulted()) {
    std::snprintf(status_.message.data(), status_.message.size(),
                  "an arm joint does not follow its command (tracking fault): the arms hold");
    return;
  }
  ++status_.commands_applied;
  // The sides a command names; kNearest is both, except for a reach (decided in reach()).
  const bool left = command.arm != ArmSide::kRight && arms_[0].present;
  const bool right = command.arm != ArmSide::kLeft && arms_[1].present;
  const std::array<bool, 2> sides{left, right};
  if (command.action != ArmAction::kGrasp && command.action != ArmAction::kRelease) {
    follower_.stop();
  }
  switch (command.action) {
    case ArmAction::kHold:
      for (int side = 0; side < 2; ++side) {
        if (sides[at(side)]) stop(side);
      }
      break;
    case ArmAction::kGrasp:
    case ArmAction::kRelease:
      set_gripper_goals(command.action, sides);
      break;
    case ArmAction::kMoveJoint:
      move_joint(command);
      break;
    case ArmAction::kReach:
      reach(command, sides, now_ns);
      break;
  }
}

void ArmReachLoop::set_gripper_goals(ArmAction action, const std::array<bool, 2>& sides) noexcept {
  for (int side = 0; side < 2; ++side) {
    if (!sides[at(side)]) continue;
    const ArmChain& chain = arms_[at(side)].chain;
    const hal::JointLimits& limits = chain.limits[4];
    arms_[at(side)].gripper_goal_rad =
        action == ArmAction::kGrasp ? limits.min_position_rad : limits.max_position_rad;
    if (action == ArmAction::kRelease) {
      // Fingers closed on something stand open by its width while the command went on closing:
      // opening starts where they are, not from the command's far side of it.
      double& opening = q_command_tree_[at(chain.joints[4])];
      opening = std::max(opening, q_believed_tree_[at(chain.joints[4])]);
    }
  }
}

bool ArmReachLoop::find_arm_joint(int rig_index, int& side, std::size_t& k) const noexcept {
  for (side = 0; side < 2; ++side) {
    const Arm& arm = arms_[at(side)];
    if (!arm.present) continue;
    for (k = 0; k < 5; ++k) {
      if (arm.chain.rig[k] == rig_index) return true;
    }
  }
  return false;
}

void ArmReachLoop::start_trajectory(std::int64_t now_ns) noexcept {
  if (tracking_.faulted()) {
    std::snprintf(status_.message.data(), status_.message.size(),
                  "an arm joint does not follow its command (tracking fault): the arms hold");
    return;
  }
  const JointTrajectory& trajectory = trajectories_.latest();
  if (trajectory.joint_count < 1 || trajectory.joint_count > JointTrajectory::kMaxJoints ||
      trajectory.point_count < 1 || trajectory.point_count > JointTrajectory::kMaxPoints) {
    std::snprintf(status_.message.data(), status_.message.size(),
                  "joint trajectory: %d joints, %d points", trajectory.joint_count,
                  trajectory.point_count);
    return;
  }
  std::array<bool, 2> arms_named{};
  for (int j = 0; j < trajectory.joint_count; ++j) {
    int side = 0;
    std::size_t k = 0;
    if (!find_arm_joint(trajectory.joint_rig_index[at(j)], side, k)) {
      std::snprintf(status_.message.data(), status_.message.size(),
                    "joint trajectory: rig joint %d is not an arm joint",
                    trajectory.joint_rig_index[at(j)]);
      return;
    }
    // The sender checked the trajectory (check_joint_trajectory); the limits are held here too.
    const hal::JointLimits& limits = arms_[at(side)].chain.limits[k];
    for (int p = 0; p < trajectory.point_count; ++p) {
      const double q = trajectory.positions_rad[at(p)][at(j)];
      if (!(q >= limits.min_position_rad && q <= limits.max_position_rad)) {
        std::snprintf(status_.message.data(), status_.message.size(),
                      "joint trajectory: point %d of rig joint %d beyond its limits", p,
                      trajectory.joint_rig_index[at(j)]);
        return;
      }
    }
    arms_named[at(side)] = true;
  }
  ++status_.commands_applied;
  for (int side = 0; side < 2; ++side) {
    if (arms_named[at(side)]) stop(side);
  }
  follower_.start(trajectory, rig_to_tree_, q_command_tree_, now_ns);
}

void ArmReachLoop::move_joint(const ArmCommand& command) noexcept {
  for (int side = 0; side < 2; ++side) {
    Arm& arm = arms_[at(side)];
    if (!arm.present) continue;
    for (std::size_t k = 0; k < 5; ++k) {
      if (arm.chain.rig[k] != command.joint_rig_index) continue;
      const hal::JointLimits& limits = arm.chain.limits[k];
      const double goal =
          std::clamp(std::isfinite(command.position_rad) ? command.position_rad
                                                         : q_command_tree_[at(arm.chain.joints[k])],
                     limits.min_position_rad, limits.max_position_rad);
      // The gripper has a goal of its own; another joint's move stops the arm's reach.
      if (k == 4) {
        arm.gripper_goal_rad = goal;
      } else {
        stop(side);
        arm.move_joint = arm.chain.joints[k];
        arm.move_goal_rad = goal;
      }
      return;
    }
  }
  std::snprintf(status_.message.data(), status_.message.size(),
                "move joint: rig joint %d is not an arm joint", command.joint_rig_index);
}

void ArmReachLoop::reach(const ArmCommand& command, const std::array<bool, 2>& sides,
                         std::int64_t now_ns) noexcept {
  Eigen::Vector3d target_W;
  if (!reach_target(command, sides, target_W)) return;
  if (command.arm != ArmSide::kNearest) {
    const int side = command.arm == ArmSide::kLeft ? 0 : 1;
    if (arms_[at(side)].present) {
      (void)start_reach(side, target_W, now_ns);
    } else {
      std::snprintf(status_.message.data(), status_.message.size(),
                    "no such arm: the rig has no %s arm", side == 0 ? "left" : "right");
    }
    return;
  }
  reach_with_nearer_arm(target_W, now_ns);
}

bool ArmReachLoop::reach_target(const ArmCommand& command, const std::array<bool, 2>& sides,
                                Eigen::Vector3d& target_W) noexcept {
  if (command.target == ReachTargetKind::kPoint) {
    target_W = Eigen::Vector3d(command.point_W_m[0], command.point_W_m[1], command.point_W_m[2]);
    return true;
  }
  // A torn read keeps the last clean status.
  if (gaze_ != nullptr) (void)gaze_->read(gaze_status_);
  const bool fixation = gaze_ != nullptr && gaze_status_.believed_fixation_valid;
  if (!fixation) {
    for (int side = 0; side < 2; ++side) {
      if (sides[at(side)]) {
        refuse(side, gaze_ == nullptr ? "no fixation: the arms have no gaze loop to ask"
                                      : "no fixation: the eyes' axes do not meet in front of them");
      }
    }
    return false;
  }
  target_W =
      Eigen::Vector3d(gaze_status_.believed_fixation_W_m[0], gaze_status_.believed_fixation_W_m[1],
                      gaze_status_.believed_fixation_W_m[2]);
  return true;
}

void ArmReachLoop::reach_with_nearer_arm(const Eigen::Vector3d& target_W,
                                         std::int64_t now_ns) noexcept {
  // The nearer shoulder first; the other arm if the nearer cannot, the nearer's reason if
  // neither can.
  int first = arms_[0].present ? 0 : 1;
  if (arms_[0].present && arms_[1].present &&
      (target_W - arms_[1].chain.shoulder_W).norm() <
          (target_W - arms_[0].chain.shoulder_W).norm()) {
    first = 1;
  }
  // A refusal the other arm makes good is no refusal: the nearer arm's status and the
  // message are put back as they were.
  const ArmStatus::Arm first_before = status_.arms[at(first)];
  const std::array<char, 160> message_before = status_.message;
  if (start_reach(first, target_W, now_ns)) return;
  const std::array<char, 160> first_message = status_.message;
  const int second = 1 - first;
  if (!arms_[at(second)].present) return;
  const ArmStatus::Arm second_before = status_.arms[at(second)];
  if (start_reach(second, target_W, now_ns)) {
    status_.arms[at(first)] = first_before;
    status_.message = message_before;
    return;
  }
  status_.arms[at(second)] = second_before;
  status_.message = first_message;
}

bool ArmReachLoop::start_reach(int side, const Eigen::Vector3d& target_W,
                               std::int64_t now_ns) noexcept {
  Arm& arm = arms_[at(side)];
  const double opening = q_command_tree_[at(arm.chain.joints[4])];
  const ReachCheck check = check_reach(arm.chain, opening, target_W, params_.hand_pitches);
  if (!check.reachable) {
    refuse(side, check.message.data());
    return false;
  }
  (void)command_kinematics_.update(q_command_tree_);
  const Eigen::Vector3d tip = tip_W(command_kinematics_, arm);
  arm.target_W = target_W;
  arm.aim_W = target_W;
  arm.q_goal_rad = check.q_rad;
  arm.approaching = false;
  // The way in: horizontal, from the shoulder's side of the target, as a level hand points.
  Eigen::Vector3d in = target_W - arm.chain.shoulder_W;
  in.z() = 0.0;
  if (in.norm() > 1e-9 && params_.approach_m > 0.0) {
    in.normalize();
    const Eigen::Vector3d approach = target_W - params_.approach_m * in;
    // Only where the arm can go, and only if the hand is not already past it.
    if ((tip - target_W).dot(in) < -params_.approach_m &&
        check_reach(arm.chain, opening, approach, params_.hand_pitches).reachable) {
      arm.approach_W = approach;
      arm.approaching = true;
    }
  } else {
    in = target_W - tip;
    in = in.norm() > 1e-9 ? Eigen::Vector3d(in.normalized()) : Eigen::Vector3d::Zero();
  }
  if (params_.probe_depth_m > 0.0 && in.norm() > 0.0) {
    // The probe only where the arm can follow it; otherwise the reach ends at the target.
    const Eigen::Vector3d aim = target_W + params_.probe_depth_m * in;
    const ReachCheck aim_check = check_reach(arm.chain, opening, aim, params_.hand_pitches);
    if (aim_check.reachable) {
      arm.aim_W = aim;
      arm.q_goal_rad = aim_check.q_rad;
    }
  }
  arm.move_joint = -1;
  arm.ramp_from_ns = now_ns;
  ArmStatus::Arm& s = status_.arms[at(side)];
  s.phase = ReachPhase::kReaching;
  s.command_ns = now_ns;
  s.touch_ns = 0;
  for (int i = 0; i < 3; ++i) s.target_W_m[at(i)] = target_W[i];
  return true;
}

void ArmReachLoop::refuse(int side, const char* why) noexcept {
  status_.arms[at(side)].phase = ReachPhase::kRefused;
  std::snprintf(status_.message.data(), status_.message.size(), "%s", why);
}

void ArmReachLoop::stop(int side) noexcept {
  ArmStatus::Arm& s = status_.arms[at(side)];
  if (s.phase == ReachPhase::kReaching) s.phase = ReachPhase::kIdle;
  arms_[at(side)].move_joint = -1;
}

void ArmReachLoop::reach_step(int side, std::int64_t now_ns, double dt_s) noexcept {
  Arm& arm = arms_[at(side)];
  ArmStatus::Arm& s = status_.arms[at(side)];
  if (stop_on_touch(arm, s, now_ns)) return;
  (void)command_kinematics_.update(q_command_tree_);
  const Eigen::Vector3d tip = tip_W(command_kinematics_, arm);
  // In front of the target near enough (a quarter of the approach): turn in without stopping.
  if (arm.approaching && (arm.approach_W - tip).norm() <= 0.25 * params_.approach_m) {
    arm.approaching = false;
  }
  const Eigen::Vector3d e_W = (arm.approaching ? arm.approach_W : arm.aim_W) - tip;
  if (!arm.approaching && e_W.norm() <= params_.arrive_tolerance_m) {
    s.phase = ReachPhase::kArrived;
    return;
  }
  Eigen::Matrix<double, 3, 4> J_v;
  tip_jacobian_W(arm, tip, J_v);
  Eigen::Vector4d qdot;
  if (!solve_joint_velocities(arm, e_W, J_v, qdot)) {
    refuse(side, "the arm servo found no motion toward the target (a singular arm)");
    return;
  }
  advance_joints(arm, arm.ramp_from_ns, now_ns, dt_s, J_v, qdot);
}

bool ArmReachLoop::stop_on_touch(Arm& arm, ArmStatus::Arm& s, std::int64_t now_ns) noexcept {
  const ArmChain& chain = arm.chain;
  hal::TouchReading reading;
  if (arm.touch == nullptr || arm.touch->read(reading) != hal::Status::kOk || !reading.in_contact) {
    return false;
  }
  // Stop where the arm is, not where it was commanded: the command leads the drives, and
  // holding it would keep pushing into what was touched.
  s.phase = ReachPhase::kTouching;
  s.touch_ns = now_ns;
  for (std::size_t k = 0; k < 4; ++k) {
    q_command_tree_[at(chain.joints[k])] = q_believed_tree_[at(chain.joints[k])];
  }
  arm.gripper_goal_rad = chain.limits[4].min_position_rad;
  return true;
}

void ArmReachLoop::tip_jacobian_W(const Arm& arm, const Eigen::Vector3d& tip,
                                  Eigen::Matrix<double, 3, 4>& J_v) noexcept {
  // The fingertips' midpoint is a point of the wrist link: v_p = v_wrist + w x (p - o_wrist).
  (void)command_kinematics_.jacobian_W(arm.wrist_frame, J_W_);
  const Eigen::Vector3d r = tip - command_kinematics_.X_WF(arm.wrist_frame).translation();
  for (int k = 0; k < 4; ++k) {
    const int column = arm.chain.joints[at(k)];
    J_v.col(k) = J_W_.block<3, 1>(0, column) - r.cross(J_W_.block<3, 1>(3, column));
  }
}

bool ArmReachLoop::solve_joint_velocities(const Arm& arm, const Eigen::Vector3d& e_W,
                                          const Eigen::Matrix<double, 3, 4>& J_v,
                                          Eigen::Vector4d& qdot) noexcept {
  const ArmChain& chain = arm.chain;
  // Secondary task: toward the reach check's joints at the aim (within every limit), the
  // gradient descent of |q - q_goal|^2 / 2. In the primary task's null space it only chooses
  // among the ways to the same fingertip motion: the elbow and the wrist's pitch, which a
  // minimum-norm law alone would drive into their limits on some ways in.
  Eigen::Vector4d u2;
  for (int k = 0; k < 4; ++k) {
    u2[k] = -params_.posture_gain_per_s *
            (q_command_tree_[at(chain.joints[at(k)])] - arm.q_goal_rad[at(k)]);
  }
  Eigen::Vector4d q, q_min, q_max;
  for (int k = 0; k < 4; ++k) {
    q[k] = q_command_tree_[at(chain.joints[at(k)])];
    q_min[k] = chain.limits[at(k)].min_position_rad;
    q_max[k] = chain.limits[at(k)].max_position_rad;
  }
  // A joint at a limit that the law drives further out is taken out of the task (its column and
  // its secondary motion zeroed) and the law solved again by the joints left: otherwise it would
  // be clamped while the others move as if it had not been, off the straight line.
  std::array<bool, 4> blocked{};
  for (int pass = 0; pass < 4; ++pass) {
    Eigen::Matrix<double, 3, 4> J_free = J_v;
    Eigen::Vector4d u2_free = u2;
    for (int k = 0; k < 4; ++k) {
      if (!blocked[at(k)]) continue;
      J_free.col(k).setZero();
      u2_free[k] = 0.0;
    }
    if (!law_->control_law(e_W, J_free, u2_free, q, q_min, q_max, qdot)) {
      return false;
    }
    bool again = false;
    for (int k = 0; k < 4; ++k) {
      const hal::JointLimits& limits = chain.limits[at(k)];
      if (!blocked[at(k)] && ((q[k] <= limits.min_position_rad && qdot[k] < 0.0) ||
                              (q[k] >= limits.max_position_rad && qdot[k] > 0.0))) {
        blocked[at(k)] = true;
        again = true;
      }
    }
    if (!again) break;
  }
  return true;
}

void ArmReachLoop::advance_joints(const Arm& arm, std::int64_t ramp_from_ns, std::int64_t now_ns,
                                  double dt_s, const Eigen::Matrix<double, 3, 4>& J_v,
                                  const Eigen::Vector4d& qdot) noexcept {
  const ArmChain& chain = arm.chain;
  // Capped speed, ramped from the reach's start or restart; every joint within its velocity limit.
  // One scale for all: the direction of motion is kept.
  const double since_s = static_cast<double>(now_ns - ramp_from_ns) * 1e-9 + dt_s;
  const double cap_m_s = std::min(params_.max_speed_m_s, params_.max_acceleration_m_s2 * since_s);
  const double speed_m_s = (J_v * qdot).norm();
  double scale = speed_m_s > cap_m_s ? cap_m_s / speed_m_s : 1.0;
  for (std::size_t k = 0; k < 4; ++k) {
    const double limit = chain.limits[k].max_velocity_rad_s;
    if (std::abs(qdot[static_cast<Eigen::Index>(k)]) * scale > limit) {
      scale = limit / std::abs(qdot[static_cast<Eigen::Index>(k)]);
    }
  }
  for (std::size_t k = 0; k < 4; ++k) {
    const hal::JointLimits& limits = chain.limits[k];
    double& q_k = q_command_tree_[at(chain.joints[k])];
    // Integrated on the clamped value: nothing winds up at a limit.
    q_k = std::clamp(q_k + scale * qdot[static_cast<Eigen::Index>(k)] * dt_s,
                     limits.min_position_rad, limits.max_position_rad);
  }
}

Eigen::Vector3d ArmReachLoop::tip_W(const Kinematics& kinematics, const Arm& arm) const noexcept {
  const double opening = kinematics.q_rad()[at(arm.chain.joints[4])];
  return kinematics.X_WF(arm.wrist_frame) * Eigen::Vector3d(arm.chain.hand_m(opening), 0.0, 0.0);
}

}  // namespace cambio::control
