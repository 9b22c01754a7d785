#include "cambio/control/gaze_loop.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace cambio::control {
namespace {

const hal::CameraInfo& stereo_camera(const hal::HardwareInfo& hardware, hal::Eye eye) {
  if (!hardware.stereo) throw std::invalid_argument("gaze loop: the rig has no stereo pair");
  const std::string& name =
      eye == hal::Eye::kLeft ? hardware.stereo->left_camera : hardware.stereo->right_camera;
  const hal::CameraInfo* camera = hardware.find_camera(name);
  if (camera == nullptr) {
    throw std::invalid_argument("gaze loop: the stereo pair names an unknown camera '" + name +
                                "'");
  }
  return *camera;
}

std::size_t at(int index) {
  return static_cast<std::size_t>(index);
}

// The head's five joints, tree order (the loop's command and belief), with their rig indices.
std::vector<CommandTracking::Joint> tracked_head_joints(const hal::HardwareInfo& hardware,
                                                        const HeadJoints& head,
                                                        std::span<const int> rig_to_tree,
                                                        const std::vector<double>& max_error_rad) {
  if (!max_error_rad.empty() && max_error_rad.size() != hardware.joints.size()) {
    throw std::invalid_argument("gaze loop: " + std::to_string(max_error_rad.size()) +
                                " tracking error limits for " +
                                std::to_string(hardware.joints.size()) + " joints");
  }
  std::vector<CommandTracking::Joint> joints;
  for (const int tree :
       {head.neck_pan, head.neck_tilt, head.eye_tilt, head.eye_pan[0], head.eye_pan[1]}) {
    CommandTracking::Joint joint;
    joint.name = hardware.joints[at(tree)].name;
    joint.index = tree;
    joint.rig = static_cast<int>(std::find(rig_to_tree.begin(), rig_to_tree.end(), tree) -
                                 rig_to_tree.begin());
    if (!max_error_rad.empty()) joint.max_error_rad = max_error_rad[at(tree)];
    joints.push_back(std::move(joint));
  }
  return joints;
}

}  // namespace

GazeLoop::GazeLoop(const hal::HardwareInfo& hardware, const GazeLoopParams& params,
                   const JointTargetFrame& pose, BelievedJoints believed,
                   const hal::SeqlockChannel<perception::SsmSummary>& summaries,
                   hal::SeqlockChannel<perception::SsmRequest>& ssm_requests,
                   const hal::SeqlockChannel<GazeCommand>& commands,
                   hal::SeqlockChannel<JointTargetFrame>& targets)
    : params_(params),
      dominant_(params.fixation.dominant_eye),
      verging_(hal::other(params.fixation.dominant_eye)),
      servo_(std::make_unique<FixationServo>(hardware, params.fixation)),
      head_(servo_->head()),
      believed_kinematics_(hardware),
      vergence_controller_(params.vergence),
      pursuit_(stereo_camera(hardware, params.fixation.dominant_eye).intrinsics,
               params.pursuit_velocity_filter_s),
      saccade_(5),
      believed_(std::move(believed)),
      summaries_(summaries),
      ssm_requests_(ssm_requests),
      commands_(commands),
      targets_(targets),
      pose_(pose) {
  if (params.vergence.verging_eye != verging_) {
    throw std::invalid_argument("gaze loop: the verging eye must be the one that is not dominant");
  }
  if (!(params.pursuit_gain_per_s > 0.0) || !(params.pursuit_lead >= 0.0)) {
    throw std::invalid_argument("gaze loop: pursuit gain must be > 0 and its lead >= 0");
  }
  const int rig_count = believed_kinematics_.rig_joint_count();
  if (pose.count != rig_count || believed_.rig_joint_count() != rig_count) {
    throw std::invalid_argument("gaze loop: the pose and the believed joints must hold the rig's " +
                                std::to_string(rig_count) + " joints");
  }
  for (const auto& joint : hardware.joints) limits_tree_.push_back(joint.limits);
  rig_to_tree_.assign(believed_kinematics_.rig_to_tree().begin(),
                      believed_kinematics_.rig_to_tree().end());
  tracking_ = CommandTracking(
      name_, tracked_head_joints(hardware, head_, rig_to_tree_, params.max_tracking_error_rad));
  const auto tree_count = static_cast<std::size_t>(believed_kinematics_.joint_count());
  q_command_tree_.assign(tree_count, 0.0);
  q_believed_tree_.assign(tree_count, 0.0);
  qdot_tree_.assign(tree_count, 0.0);
  q_believed_rig_.assign(static_cast<std::size_t>(rig_count), 0.0);
  for (int i = 0; i < rig_count; ++i) {
    const double q = pose.commands[at(i)].value;
    q_command_tree_[at(rig_to_tree_[at(i)])] = q;
    q_believed_rig_[at(i)] = q;
  }
  q_believed_tree_ = q_command_tree_;
  q_scratch_tree_ = q_command_tree_;
  saccade_joints_ = {head_.neck_pan, head_.neck_tilt, head_.eye_tilt,
                     head_.eye_pan[static_cast<std::size_t>(dominant_)],
                     head_.eye_pan[static_cast<std::size_t>(verging_)]};
  for (std::size_t k = 0; k < saccade_joints_.size(); ++k) {
    const hal::JointLimits& limits = limits_tree_[at(saccade_joints_[k])];
    saccade_vmax_[k] = limits.max_velocity_rad_s;
    saccade_amax_[k] = limits.max_acceleration_rad_s2;
  }
  // Whatever the initial pose, the eyes start no further apart than parallel.
  const double left = q_command_tree_[at(head_.eye_pan[0])];
  const double right = q_command_tree_[at(head_.eye_pan[1])];
  vergence_rad_ = right - left;
  clamp_vergence();
  place_verging_eye();
  (void)believed_kinematics_.update(q_believed_tree_);
}

GazeLoop::~GazeLoop() = default;

void GazeLoop::set_overlay(const hal::SeqlockChannel<JointTargetFrame>* overlay,
                           std::vector<int> rig_indices) {
  const std::array<int, 5> head{head_.neck_pan, head_.neck_tilt, head_.eye_tilt, head_.eye_pan[0],
                                head_.eye_pan[1]};
  for (const int i : rig_indices) {
    if (i < 0 || i >= pose_.count) {
      throw std::invalid_argument("gaze loop: overlay joint " + std::to_string(i) +
                                  " is outside the rig's " + std::to_string(pose_.count) +
                                  " joints");
    }
    if (std::find(head.begin(), head.end(), rig_to_tree_[at(i)]) != head.end()) {
      throw std::invalid_argument("gaze loop: overlay joint " + std::to_string(i) +
                                  " is a head joint, which the gaze loop commands");
    }
  }
  overlay_ = overlay;
  overlay_rig_indices_ = std::move(rig_indices);
}

void GazeLoop::activate() {
  request_features();
  for (auto& sample : camera_poses_) sample = CameraPoseSample{};
  camera_pose_next_ = 0;
}

hal::Status GazeLoop::update(const hal::LoopTick& tick) noexcept {
  const std::int64_t now_ns = tick.now_ns;
  const double dt_s = tick.period_s;
  GazeCommand command;
  if (commands_.read(command) && command.sequence != 0 &&
      command.sequence != last_command_sequence_) {
    last_command_sequence_ = command.sequence;
    apply(command, now_ns);
  }
  if (trajectories_.take_new()) start_trajectory(now_ns);
  update_belief(now_ns);
  const CommandTracking::Step tracking = tracking_.step(believed_);
  // An unwritten channel holds FeatureRequest{} (everything): nobody asked for it yet.
  if (extra_features_channel_ != nullptr && extra_features_channel_->version() > 0) {
    perception::FeatureRequest extra;
    if (extra_features_channel_->read(extra) &&
        (extra.maps != extra_features_.maps || extra.disparity != extra_features_.disparity ||
         extra.motion != extra_features_.motion || extra.moments != extra_features_.moments ||
         extra.region != extra_features_.region)) {
      extra_features_ = extra;
      request_features();
    }
  }

  // A mode changed without a command (a saccade's end) changes what the SSM must compute.
  if (request_.features.region != wants_region()) request_features();
  (void)summaries_.read(summary_);  // A torn read keeps the last clean summary.
  status_.joints_held = tracking == CommandTracking::Step::kFrozen;
  switch (tracking) {
    case CommandTracking::Step::kFollow:
      break;
    case CommandTracking::Step::kFrozen:
      // The drives do not follow: what is commanded stays as it was, so nothing winds up.
      write_targets(now_ns);
      publish(now_ns);
      return hal::Status::kOk;
    case CommandTracking::Step::kRestart:
      // The first command after a hold is where the joints are; motion resumes next cycle.
      restart_from_measured(now_ns);
      write_targets(now_ns);
      publish(now_ns);
      return hal::Status::kOk;
    case CommandTracking::Step::kFaulted:
      write_targets(now_ns);
      publish(now_ns);
      return hal::Status::kFault;
  }

  // A measurement is taken on a cycle the controller follows: one that arrives while it is frozen
  // waits for it. (Over a loaded CAN bus the holds come right after a camera frame's render, just
  // when the SSM's result lands: consumed there, every measurement was lost and the eyes never
  // verged.)
  const bool new_summary = summary_.sequence != 0 && summary_.sequence != last_summary_sequence_;
  if (new_summary) {
    last_summary_sequence_ = summary_.sequence;
    ++measurements_;
  }

  switch (mode_) {
    case Mode::kHold:
      if (move_joint_ >= 0) step_move(dt_s);
      break;
    case Mode::kTrajectory:
      if (!follower_.step(now_ns, q_command_tree_)) {
        // The last point written: the head holds there, vergence as the trajectory left it.
        mode_ = Mode::kHold;
        vergence_rad_ = commanded_vergence_rad();
        verged_ = false;
      }
      break;
    case Mode::kFixate:
      servo_step(1.0, dt_s);
      break;
    case Mode::kPursue: {
      if (new_summary) {
        pursuit_.update(summary_.motion[static_cast<std::size_t>(dominant_)],
                        R_WC_at(summary_.stamp_ns), summary_.stamp_ns, summary_.region,
                        summary_.fixation[static_cast<std::size_t>(dominant_)]);
      }
      // Extrapolated by the law's lag, so a steadily moving target is followed without it.
      const double lead_s = params_.pursuit_lead / params_.pursuit_gain_per_s;
      const auto lead_ns = static_cast<std::int64_t>(lead_s * 1e9);
      const Eigen::Vector3d c_W =
          believed_kinematics_.X_WF(head_.camera_frame[static_cast<std::size_t>(dominant_)])
              .translation();
      target_W_ << c_W + pursuit_depth_m_ * pursuit_.direction_W(now_ns + lead_ns), 1.0;
      servo_step(params_.pursuit_gain_per_s / params_.fixation.gain_per_s, dt_s);
      break;
    }
    case Mode::kSaccade: {
      const double t_s = static_cast<double>(now_ns - saccade_start_ns_) * 1e-9;
      saccade_.sample(std::min(t_s, saccade_.duration_s()), saccade_q_, saccade_qdot_);
      for (std::size_t k = 0; k < saccade_joints_.size(); ++k) {
        q_command_tree_[at(saccade_joints_[k])] = saccade_q_[k];
      }
      if (t_s >= saccade_.duration_s()) {
        // The dominant eye has stopped on the target: fixate it and let the other eye re-verge.
        mode_ = Mode::kFixate;
        vergence_rad_ = saccade_end_vergence_rad_;
        verged_ = false;
        anchored_ = false;
        elsewhere_since_ns_.reset();
        pending_jump_rad_ = 0.0;
        weak_pending_ = false;
        faint_agreements_ = 0;
        vergence_blind_until_ns_ = now_ns;
      }
      break;
    }
  }
  if (mode_ != Mode::kSaccade && mode_ != Mode::kTrajectory) {
    if (new_summary && verge_ && params_.vergence_enabled) verge(summary_);
    clamp_vergence();
    place_verging_eye();
  }
  if (tracking_.check(q_command_tree_, q_believed_tree_)) {
    stop_on_tracking_fault();
    write_targets(now_ns);
    publish(now_ns);
    return report_fault(tracking_.fault_message());
  }
  write_targets(now_ns);
  publish(now_ns);
  return hal::Status::kOk;
}

void GazeLoop::write_targets(std::int64_t now_ns) noexcept {
  for (int i = 0; i < pose_.count; ++i) {
    pose_.commands[at(i)].value = q_command_tree_[at(rig_to_tree_[at(i)])];
  }
  if (overlay_ != nullptr) {
    (void)overlay_->read(overlay_frame_);  // A torn read keeps the last clean frame.
    if (overlay_frame_.count == pose_.count) {
      for (const int i : overlay_rig_indices_)
        pose_.commands[at(i)] = overlay_frame_.commands[at(i)];
    }
  }
  pose_.stamp_ns = now_ns;
  targets_.write(pose_);
}

void GazeLoop::restart_from_measured(std::int64_t now_ns) noexcept {
  tracking_.restart(q_command_tree_, q_believed_tree_);
  // The vergence the eyes have, within what the verging eye may do.
  vergence_rad_ = commanded_vergence_rad();
  clamp_vergence();
  // A disparity measured while the eyes were held belongs to a vergence no longer commanded.
  verged_ = false;
  pending_jump_rad_ = 0.0;
  weak_pending_ = false;
  faint_agreements_ = 0;
  if (mode_ == Mode::kSaccade) start_saccade(now_ns);
  if (mode_ == Mode::kTrajectory) {
    follower_.stop();
    mode_ = Mode::kHold;
  }
}

void GazeLoop::step_move(double dt_s) noexcept {
  const std::size_t joint = at(move_joint_);
  const double step = limits_tree_[joint].max_velocity_rad_s * dt_s;
  double& q = q_command_tree_[joint];
  const bool arrives = std::abs(move_goal_rad_ - q) <= step;
  q = arrives ? move_goal_rad_ : q + std::clamp(move_goal_rad_ - q, -step, step);
  if (move_joint_ == head_.eye_pan[0] || move_joint_ == head_.eye_pan[1]) {
    // The verging eye keeps the vergence this move gives it (place_verging_eye() would undo it).
    vergence_rad_ = commanded_vergence_rad();
  }
  if (arrives) move_joint_ = -1;
}

double GazeLoop::commanded_vergence_rad() const noexcept {
  const double sign = verging_ == hal::Eye::kRight ? 1.0 : -1.0;
  return sign * (q_command_tree_[at(head_.eye_pan[static_cast<std::size_t>(verging_)])] -
                 q_command_tree_[at(head_.eye_pan[static_cast<std::size_t>(dominant_)])]);
}

void GazeLoop::stop_on_tracking_fault() noexcept {
  tracking_.restart(q_command_tree_, q_believed_tree_);
  vergence_rad_ = commanded_vergence_rad();
  mode_ = Mode::kHold;
  move_joint_ = -1;
  follower_.stop();
  pursuit_.stop();
  status_.tracking_fault = true;
}

void GazeLoop::apply(const GazeCommand& command, std::int64_t now_ns) noexcept {
  if (command.action == GazeAction::kVerge) {
    verge_ = command.verge;
    verged_ = false;
    ++status_.commands_applied;
    return;
  }
  if (tracking_.faulted()) {
    refuse(GazeRefusal::kTrackingFault);
    return;
  }
  move_joint_ = -1;
  follower_.stop();
  command_ = command;
  verge_ = command.verge;
  verged_ = false;  // A new gaze target: its first measurements are believed as they come.
  anchored_ = false;
  elsewhere_since_ns_.reset();
  pending_jump_rad_ = 0.0;
  weak_pending_ = false;
  faint_agreements_ = 0;
  ++status_.commands_applied;
  status_.action = command.action;
  switch (command.action) {
    case GazeAction::kHold:
      mode_ = Mode::kHold;
      break;
    case GazeAction::kFixate:
    case GazeAction::kSaccade: {
      Eigen::Vector4d target;
      if (!resolve(command.target, target)) {
        refuse(GazeRefusal::kTargetUnresolved);
        mode_ = Mode::kHold;
        break;
      }
      target_W_ = target;
      target_set_ = true;
      if (command.action == GazeAction::kSaccade) {
        start_saccade(now_ns);
      } else {
        mode_ = Mode::kFixate;
      }
      break;
    }
    case GazeAction::kPursue: {
      const Eigen::Isometry3d& X_WC =
          believed_kinematics_.X_WF(head_.camera_frame[static_cast<std::size_t>(dominant_)]);
      pursuit_depth_m_ = depth_estimate_m();
      // The last frame's region was seen while the eyes fixated the target now pursued.
      pursuit_.start(X_WC.linear().col(2), X_WC.linear(), now_ns, summary_.region,
                     summary_.fixation[static_cast<std::size_t>(dominant_)]);
      target_W_ << X_WC.translation() + pursuit_depth_m_ * X_WC.linear().col(2), 1.0;
      target_set_ = true;
      mode_ = Mode::kPursue;
      break;
    }
    case GazeAction::kMoveJoint:
      mode_ = Mode::kHold;
      if (!move_joint(command.joint_rig_index, command.position_rad)) {
        refuse(GazeRefusal::kNotAHeadJoint);
      }
      break;
    case GazeAction::kVerge:
      break;  // Handled above.
  }
  if (mode_ != Mode::kPursue) pursuit_.stop();
  request_features();
}

void GazeLoop::start_trajectory(std::int64_t now_ns) noexcept {
  if (tracking_.faulted()) {
    refuse(GazeRefusal::kTrackingFault);
    return;
  }
  const JointTrajectory& trajectory = trajectories_.latest();
  bool valid = trajectory.joint_count >= 1 &&
               trajectory.joint_count <= JointTrajectory::kMaxJoints &&
               trajectory.point_count >= 1 && trajectory.point_count <= JointTrajectory::kMaxPoints;
  for (int j = 0; valid && j < trajectory.joint_count; ++j) {
    const int rig_index = trajectory.joint_rig_index[at(j)];
    valid = rig_index >= 0 && rig_index < pose_.count && is_head_joint(rig_to_tree_[at(rig_index)]);
  }
  // The sender checked the trajectory against the limits (check_joint_trajectory); what reaches
  // the drives is clamped all the same.
  for (int k = 0; valid && k < trajectory.point_count; ++k) {
    for (int j = 0; valid && j < trajectory.joint_count; ++j) {
      const hal::JointLimits& limits =
          limits_tree_[at(rig_to_tree_[at(trajectory.joint_rig_index[at(j)])])];
      const double q = trajectory.positions_rad[at(k)][at(j)];
      valid = q >= limits.min_position_rad && q <= limits.max_position_rad;
    }
  }
  if (!valid) {
    refuse(GazeRefusal::kNotAHeadJoint);
    return;
  }
  ++status_.commands_applied;
  move_joint_ = -1;
  pursuit_.stop();
  mode_ = Mode::kTrajectory;
  follower_.start(trajectory, rig_to_tree_, q_command_tree_, now_ns);
}

bool GazeLoop::is_head_joint(int tree_index) const noexcept {
  return tree_index == head_.neck_pan || tree_index == head_.neck_tilt ||
         tree_index == head_.eye_tilt || tree_index == head_.eye_pan[0] ||
         tree_index == head_.eye_pan[1];
}

bool GazeLoop::move_joint(int rig_index, double position_rad) noexcept {
  if (rig_index < 0 || rig_index >= pose_.count || !std::isfinite(position_rad)) return false;
  const int joint = rig_to_tree_[at(rig_index)];
  if (!is_head_joint(joint)) return false;  // The arms' joints are the arm loop's.
  const hal::JointLimits& limits = limits_tree_[at(joint)];
  // Not a step to the goal: the command would lead the joint by the whole move (update() ramps).
  move_joint_ = joint;
  move_goal_rad_ = std::clamp(position_rad, limits.min_position_rad, limits.max_position_rad);
  return true;
}

bool GazeLoop::resolve(const GazeTarget& target, Eigen::Vector4d& target_W) const noexcept {
  const Eigen::Isometry3d& X_WC =
      believed_kinematics_.X_WF(head_.camera_frame[static_cast<std::size_t>(dominant_)]);
  const double depth_m = depth_estimate_m();
  Eigen::Vector3d ray_W;
  switch (target.kind) {
    case GazeTargetKind::kPoint: {
      target_W << target.point_W_m[0], target.point_W_m[1], target.point_W_m[2], 1.0;
      // Finite is not enough (1e300 squared is not): a point the eyes can turn to is within
      // kMaxTargetDistance_m and not at the camera's centre. Whoever sent it (console, experiment,
      // behaviour) gets a refused command; nothing non-finite reaches the servo's state.
      const double distance_m = (target_W.head<3>() - X_WC.translation()).norm();
      return target_W.allFinite() && distance_m <= kMaxTargetDistance_m &&
             distance_m >= kMinTargetDistance_m;
    }
    case GazeTargetKind::kPixel:
      ray_W = servo_->pixel_ray_W(q_believed_tree_, target.pixel_px[0], target.pixel_px[1]);
      break;
    case GazeTargetKind::kAngles: {
      // Camera frame: x right, y down; pan to the left is -x, tilt down is +y.
      const Eigen::Vector3d ray_C(-std::tan(target.angles_rad[0]), std::tan(target.angles_rad[1]),
                                  1.0);
      ray_W = X_WC.linear() * ray_C.normalized();
      break;
    }
    case GazeTargetKind::kNone:
      return false;
  }
  target_W << X_WC.translation() + depth_m * ray_W, 1.0;
  return target_W.allFinite();
}

void GazeLoop::start_saccade(std::int64_t now_ns) noexcept {
  q_scratch_tree_ = q_command_tree_;  // Same size: no allocation.
  if (servo_->solve(q_command_tree_, target_W_, vergence_rad_, q_scratch_tree_) !=
      hal::Status::kOk) {
    refuse(GazeRefusal::kOutOfReach);
    mode_ = Mode::kFixate;  // Servo there instead, at the servo's pace.
    return;
  }
  saccade_end_vergence_rad_ = vergence_rad_;
  const std::size_t dominant_pan = at(head_.eye_pan[static_cast<std::size_t>(dominant_)]);
  const std::size_t verging_pan = at(head_.eye_pan[static_cast<std::size_t>(verging_)]);
  if (params_.predictive_vergence && command_.target.kind == GazeTargetKind::kPoint) {
    // The vergence the target's depth needs at the end pose: turn the verging eye's axis onto it.
    (void)believed_kinematics_.update(q_scratch_tree_);  // Restored by the next update_belief().
    const Eigen::Isometry3d& X_WV =
        believed_kinematics_.X_WF(head_.camera_frame[static_cast<std::size_t>(verging_)]);
    const Eigen::Vector3d p_V = X_WV.inverse() * target_W_.head<3>();
    if (p_V.z() > 0.0) {
      const double turn_left_rad = std::atan2(-p_V.x(), p_V.z());
      const double verging_end = q_scratch_tree_[verging_pan] + turn_left_rad;
      saccade_end_vergence_rad_ = verging_ == hal::Eye::kRight
                                      ? verging_end - q_scratch_tree_[dominant_pan]
                                      : q_scratch_tree_[dominant_pan] - verging_end;
    }
  }
  const double sign = verging_ == hal::Eye::kRight ? 1.0 : -1.0;
  const hal::JointLimits& verging_limits = limits_tree_[verging_pan];
  q_scratch_tree_[verging_pan] =
      std::clamp(q_scratch_tree_[dominant_pan] + sign * std::max(saccade_end_vergence_rad_, 0.0),
                 verging_limits.min_position_rad, verging_limits.max_position_rad);
  for (std::size_t k = 0; k < saccade_joints_.size(); ++k) {
    saccade_q0_[k] = q_command_tree_[at(saccade_joints_[k])];
    saccade_q1_[k] = q_scratch_tree_[at(saccade_joints_[k])];
  }
  if (!std::isfinite(saccade_.plan(saccade_q0_, saccade_q1_, saccade_vmax_, saccade_amax_))) {
    // No plan (a joint with no velocity or acceleration limit to plan with): the old plan is
    // kept, and must not be replayed towards this target. The head holds where it is.
    refuse(GazeRefusal::kSaccadeUnplannable);
    mode_ = Mode::kHold;
    return;
  }
  saccade_start_ns_ = now_ns;
  mode_ = Mode::kSaccade;
}

void GazeLoop::refuse(GazeRefusal why) noexcept {
  ++rejected_commands_;
  ++status_.commands_refused;
  status_.last_refusal = why;
}

void GazeLoop::servo_step(double gain_scale, double dt_s) noexcept {
  if (servo_->velocity(q_command_tree_, target_W_, vergence_rad_, qdot_tree_, &fixation_error_) !=
      hal::Status::kOk) {
    return;  // Nothing to servo on (the target behind the eye): hold.
  }
  for (std::size_t k = 0; k < 4; ++k) {
    const std::size_t joint = at(saccade_joints_[k]);
    const hal::JointLimits& limits = limits_tree_[joint];
    const double qdot = std::clamp(gain_scale * qdot_tree_[joint], -limits.max_velocity_rad_s,
                                   limits.max_velocity_rad_s);
    // Integrated on the clamped value: nothing winds up at a limit.
    q_command_tree_[joint] = std::clamp(q_command_tree_[joint] + qdot * dt_s,
                                        limits.min_position_rad, limits.max_position_rad);
  }
}

void GazeLoop::verge(const perception::SsmSummary& summary) noexcept {
  const auto& disparity = summary.disparity;
  const double d_px = static_cast<double>(disparity.disparity_px);
  const double confidence = static_cast<double>(disparity.confidence);
  if (anchored_ && verging_fovea_changed(summary)) verging_view_changed_ = true;
  if (!disparity.valid || !std::isfinite(d_px) || summary.stamp_ns < vergence_blind_until_ns_) {
    return;
  }
  // The angle the verging eye must still turn (sign as applied to its pan).
  const double error_rad = vergence_controller_.angular_error_rad(d_px);
  // The vergence this measurement asks for (as the steps below apply it).
  const double asked_rad = vergence_rad_ + (verging_ == hal::Eye::kRight ? error_rad : -error_rad);
  const bool faint = !(confidence >= params_.vergence.min_confidence / 3.0);
  if (faint && !faint_reading_persists(error_rad, asked_rad)) return;
  if (anchored_ && std::abs(asked_rad - anchor_rad_) <= kAnchorAgreementRad &&
      std::abs(vergence_rad_ - anchor_rad_) > kVergenceJumpRad) {
    // The surface the eyes were verged on is seen again (whatever had drawn the verging eye off
    // has gone): go back to it at once rather than converge on it again.
    vergence_rad_ = anchor_rad_;
    verged_ = true;
    pending_jump_rad_ = 0.0;
    weak_pending_ = false;
    faint_agreements_ = 0;
    elsewhere_since_ns_.reset();
    ++anchor_returns_;
    return;
  }
  if (!faint && confidence < params_.vergence.min_confidence) {
    // A weak measurement is believed when the next one agrees with it, as it stands or less what
    // the eye has turned since (the frame may predate the turn): two frames' noise rarely agrees
    // on a disparity by chance. A periodic texture's alias can; the margin in the confidence
    // keeps such measurements weak, not absent, and the jump rule below still applies.
    const bool agrees =
        weak_pending_ && readings_agree(error_rad, weak_error_rad_, applied_since_weak_rad_);
    weak_pending_ = true;
    weak_error_rad_ = error_rad;
    applied_since_weak_rad_ = 0.0;
    if (!agrees) return;
  }
  // Once verged on an anchor, a reading that asks to leave it, with much less confidence than
  // the readings that verified it, is not followed: an object edging into the verging eye's
  // window reads a little off the target before it reads its own depth, and weak evidence must
  // not drag the eyes off a surface they see well.
  if (verged_ && anchored_ && std::abs(asked_rad - anchor_rad_) > kAnchorAgreementRad &&
      confidence < kDepartureConfidenceShare * anchor_confidence_) {
    ++doubtful_departures_;
    return;
  }
  // Once verged, a sudden large error is believed only when the next measurement confirms it
  // (same direction, within a factor of two): an object crossing the line of sight, seen by the
  // SSM a frame or two late, must not drag the eyes off a target they still see.
  if (verged_) {
    // The fixated surface is still where the dominant eye looks, so its depth has not jumped.
    const bool against_anchor = anchored_ && std::abs(asked_rad - anchor_rad_) > kVergenceJumpRad &&
                                dominant_fovea_steady(summary);
    // Only the fovea's own match (its finest level, a scan decided on the fovea's window) is
    // covered by the verging fovea's motion check; wider windows may hold a distractor.
    const bool foveal_reading = disparity.level == 0 && disparity.scan_window_tier <= 0 &&
                                confidence >= params_.vergence.min_confidence;
    if (against_anchor && (verging_view_changed_ || !foveal_reading)) {
      // Something has come into the verging eye's view: it sees that, in front of the target;
      // or a reading from wider windows (a distractor there) disputes the anchor. Keep the
      // vergence.
      ++occlusion_rejections_;
      pending_jump_rad_ = 0.0;
      return;
    }
    if (std::abs(error_rad) > kVergenceJumpRad) {
      const bool confirms = std::abs(pending_jump_rad_) > kVergenceJumpRad &&
                            error_rad * pending_jump_rad_ > 0.0 &&
                            std::abs(error_rad) <= 2.0 * std::abs(pending_jump_rad_) &&
                            std::abs(pending_jump_rad_) <= 2.0 * std::abs(error_rad);
      if (!confirms) {
        pending_jump_rad_ = error_rad;
        pending_jump_since_ns_ = summary.stamp_ns;
        ++held_jumps_;
        return;
      }
      const bool from_anchor = anchored_ && std::abs(asked_rad - anchor_rad_) > kVergenceJumpRad;
      const double jump_age_s =
          static_cast<double>(summary.stamp_ns - pending_jump_since_ns_) * 1e-9;
      if (from_anchor && !against_anchor && jump_age_s < kJumpFromAnchorAfter_s) {
        pending_jump_rad_ = error_rad;  // Still confirming: the next reading is compared to it.
        ++held_jumps_;
        return;
      }
      verged_ = false;  // A real change of depth: verge again as from the start.
      if (against_anchor) {
        // Neither fovea has changed since the anchor was verged on, yet the same view now
        // reads another depth, confidently and twice: the anchor was the false match (a
        // periodic texture's alias seen on the way in). Forget it rather than return to it.
        anchored_ = false;
        elsewhere_since_ns_.reset();
        ++false_anchors_;
      }
    }
  }
  pending_jump_rad_ = 0.0;
  if (std::abs(error_rad) < kVergedRad) verged_ = true;
  const double step = std::clamp(params_.vergence.gain * error_rad, -params_.vergence.max_step_rad,
                                 params_.vergence.max_step_rad);
  vergence_rad_ += verging_ == hal::Eye::kRight ? step : -step;
  if (std::abs(error_rad) < kVergedRad) anchor_on(summary.stamp_ns, confidence);
  applied_since_weak_rad_ += step;
  applied_since_faint_rad_ += step;
  ++corrections_;
}

bool GazeLoop::readings_agree(double error_rad, double earlier_error_rad,
                              double applied_since_rad) noexcept {
  // As the earlier reading stands, or less what the eye has turned since (the frame may predate
  // the turn).
  const double tolerance = kWeakAgreementRad + 0.1 * std::abs(error_rad);
  return std::abs(error_rad - earlier_error_rad) <= tolerance ||
         std::abs(error_rad - (earlier_error_rad - applied_since_rad)) <= tolerance;
}

bool GazeLoop::faint_reading_persists(double error_rad, double asked_rad) noexcept {
  // A surface verged on since the command is not left on faint evidence; near it, faint readings
  // still refine the vergence.
  if ((verged_ || anchored_) &&
      !(anchored_ && std::abs(asked_rad - anchor_rad_) <= kAnchorAgreementRad)) {
    faint_agreements_ = 0;
    return false;
  }
  const bool agrees = faint_agreements_ > 0 &&
                      readings_agree(error_rad, faint_error_rad_, applied_since_faint_rad_);
  faint_agreements_ = agrees ? faint_agreements_ + 1 : 1;
  faint_error_rad_ = error_rad;
  applied_since_faint_rad_ = 0.0;
  // Each further reading that agrees extends the run and is followed too.
  if (faint_agreements_ < kFaintAgreements) return false;
  ++faint_steps_;
  return true;
}

void GazeLoop::anchor_on(std::int64_t stamp_ns, double confidence) noexcept {
  if (!anchored_ || std::abs(vergence_rad_ - anchor_rad_) <= kVergenceJumpRad) {
    // The fixated surface's vergence, followed while it moves smoothly. Its confidence is the
    // strongest of the recent readings that verified it: an object edging into the window first
    // weakens a reading at the anchor, and that must not lower the bar for the next, which
    // already reads the object.
    anchor_confidence_ =
        anchored_ ? std::max(confidence, kAnchorConfidenceHold * anchor_confidence_) : confidence;
    anchor_rad_ = vergence_rad_;
    anchored_ = true;
    verging_view_changed_ = false;
    elsewhere_since_ns_.reset();
    return;
  }
  // Verged on a surface at another depth: something that crossed the dominant eye's view too,
  // or the target itself. Only a surface held for kReanchorAfter_s replaces the anchor; until
  // then the anchored one is returned to as soon as it is measured again.
  if (!elsewhere_since_ns_ || std::abs(vergence_rad_ - elsewhere_rad_) > kVergenceJumpRad) {
    elsewhere_since_ns_ = stamp_ns;
  } else if (static_cast<double>(stamp_ns - *elsewhere_since_ns_) * 1e-9 >= kReanchorAfter_s) {
    anchor_rad_ = vergence_rad_;
    anchor_confidence_ = confidence;
    verging_view_changed_ = false;
    elsewhere_since_ns_.reset();
    ++reanchors_;
    return;
  }
  elsewhere_rad_ = vergence_rad_;
}

bool GazeLoop::dominant_fovea_steady(const perception::SsmSummary& summary) const noexcept {
  const perception::MotionResult& motion = summary.motion[static_cast<std::size_t>(dominant_)];
  if (!motion.valid || motion.level != 0) return false;
  const perception::LevelMotion& fovea = motion.per_level[0];
  return std::hypot(motion.flow_x_px, motion.flow_y_px) < kSteadyFlowPx &&
         fovea.residual_rms < kSteadyResidualGrey;
}

bool GazeLoop::verging_fovea_changed(const perception::SsmSummary& summary) const noexcept {
  const perception::MotionResult& motion = summary.motion[static_cast<std::size_t>(verging_)];
  return !motion.valid || motion.level != 0 ||
         !(motion.per_level[0].residual_rms < kSteadyResidualGrey);
}

void GazeLoop::clamp_vergence() noexcept {
  const std::size_t dominant_pan = at(head_.eye_pan[static_cast<std::size_t>(dominant_)]);
  const std::size_t verging_pan = at(head_.eye_pan[static_cast<std::size_t>(verging_)]);
  const double dominant = q_command_tree_[dominant_pan];
  const hal::JointLimits& limits = limits_tree_[verging_pan];
  // verging = dominant + v (right eye verging) or dominant - v (left eye verging), v >= 0.
  const double low = verging_ == hal::Eye::kRight ? limits.min_position_rad - dominant
                                                  : dominant - limits.max_position_rad;
  const double high = verging_ == hal::Eye::kRight ? limits.max_position_rad - dominant
                                                   : dominant - limits.min_position_rad;
  const double floor = std::max(0.0, low);
  vergence_rad_ =
      std::clamp(std::isfinite(vergence_rad_) ? vergence_rad_ : 0.0, floor, std::max(floor, high));
}

void GazeLoop::place_verging_eye() noexcept {
  const std::size_t dominant_pan = at(head_.eye_pan[static_cast<std::size_t>(dominant_)]);
  const std::size_t verging_pan = at(head_.eye_pan[static_cast<std::size_t>(verging_)]);
  const double sign = verging_ == hal::Eye::kRight ? 1.0 : -1.0;
  const hal::JointLimits& limits = limits_tree_[verging_pan];
  q_command_tree_[verging_pan] = std::clamp(q_command_tree_[dominant_pan] + sign * vergence_rad_,
                                            limits.min_position_rad, limits.max_position_rad);
}

double GazeLoop::depth_estimate_m() const noexcept {
  if (status_.believed_fixation_valid) {
    const Eigen::Vector3d c_W =
        believed_kinematics_.X_WF(head_.camera_frame[static_cast<std::size_t>(dominant_)])
            .translation();
    const Eigen::Vector3d p_W(status_.believed_fixation_W_m[0], status_.believed_fixation_W_m[1],
                              status_.believed_fixation_W_m[2]);
    const double depth = (p_W - c_W).norm();
    if (depth > 0.05 && depth < 20.0) return depth;
  }
  return params_.fixation.default_depth_m;
}

const Eigen::Matrix3d& GazeLoop::R_WC_at(std::int64_t stamp_ns) const noexcept {
  // The newest sample not after the stamp; the oldest one if all are after it.
  const CameraPoseSample* best = nullptr;
  const CameraPoseSample* oldest = &camera_poses_[0];
  for (const auto& sample : camera_poses_) {
    if (sample.stamp_ns == 0) continue;
    if (oldest->stamp_ns == 0 || sample.stamp_ns < oldest->stamp_ns) oldest = &sample;
    if (sample.stamp_ns <= stamp_ns && (best == nullptr || sample.stamp_ns > best->stamp_ns)) {
      best = &sample;
    }
  }
  return best != nullptr ? best->R_WC : oldest->R_WC;
}

void GazeLoop::update_belief(std::int64_t now_ns) noexcept {
  (void)believed_.read(q_believed_rig_);
  for (std::size_t i = 0; i < q_believed_rig_.size(); ++i) {
    q_believed_tree_[at(rig_to_tree_[i])] = q_believed_rig_[i];
  }
  (void)believed_kinematics_.update(q_believed_tree_);
  CameraPoseSample& sample = camera_poses_[camera_pose_next_];
  sample.stamp_ns = now_ns;
  sample.R_WC =
      believed_kinematics_.X_WF(head_.camera_frame[static_cast<std::size_t>(dominant_)]).linear();
  camera_pose_next_ = (camera_pose_next_ + 1) % camera_poses_.size();
}

void GazeLoop::publish(std::int64_t now_ns) noexcept {
  status_.stamp_ns = now_ns;
  status_.saccade_active = mode_ == Mode::kSaccade;
  status_.trajectory_active = mode_ == Mode::kTrajectory;
  status_.target_set = target_set_;
  if (target_set_) {
    for (int i = 0; i < 3; ++i) status_.target_W_m[at(i)] = target_W_[i];
  }
  // Where the robot believes it looks: the point nearest both believed optical axes.
  const Eigen::Isometry3d& X_WL = believed_kinematics_.X_WF(head_.camera_frame[0]);
  const Eigen::Isometry3d& X_WR = believed_kinematics_.X_WF(head_.camera_frame[1]);
  const Eigen::Vector3d p1 = X_WL.translation();
  const Eigen::Vector3d d1 = X_WL.linear().col(2);
  const Eigen::Vector3d p2 = X_WR.translation();
  const Eigen::Vector3d d2 = X_WR.linear().col(2);
  const Eigen::Vector3d w0 = p1 - p2;
  const double b = d1.dot(d2);
  const double d = d1.dot(w0);
  const double e = d2.dot(w0);
  const double denominator = 1.0 - b * b;
  status_.believed_fixation_valid = false;
  if (denominator > 1e-12) {
    const double s = (b * e - d) / denominator;
    const double t = (e - b * d) / denominator;
    if (s > 0.0 && t > 0.0) {
      const Eigen::Vector3d point = 0.5 * (p1 + s * d1 + p2 + t * d2);
      for (int i = 0; i < 3; ++i) status_.believed_fixation_W_m[at(i)] = point[i];
      status_.believed_fixation_valid = true;
    }
  }
  status_.vergence_rad =
      q_command_tree_[at(head_.eye_pan[1])] - q_command_tree_[at(head_.eye_pan[0])];
  status_.disparity_valid = summary_.disparity.valid;
  status_.disparity_px = summary_.disparity.disparity_px;
  status_.disparity_confidence = summary_.disparity.confidence;
  status_.feature_error_px = fixation_error_.error_px;
  status_channel_.write(status_);
}

void GazeLoop::request_features() noexcept {
  request_.fixation_set = false;  // Both retinas on their image centres: the eyes' axes.
  request_.features.maps = perception::kAllMaps | extra_features_.maps;
  request_.features.disparity = true;
  // Motion always: pursuit follows it, and vergence tells an occlusion of the verging eye from
  // a change of the fixated surface by whether the dominant fovea moved.
  request_.features.motion = true;
  request_.features.moments = extra_features_.moments;
  // The fixated object's region while fixating too: pursuit starts from the last one seen there.
  request_.features.region = wants_region();
  ssm_requests_.write(request_);
}

}  // namespace cambio::control
