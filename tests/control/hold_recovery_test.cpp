// The controllers over a real joint loop while the drives hold: a fake rig (every group of the
// shipped rig; enabled joints go where the joint loop sends them) faults its head for a second
// in the middle of a saccade and of a reach. The joint loop latches the fault, holds every joint
// and recovers by itself (reset, enable at the measured pose). What is checked against the fake
// drives' own positions: the controllers' commands do not move while the joints hold; the first
// command after the hold is the measured pose; no joint then moves faster than its velocity
// limit; the saccade and the reach still end where they were going. A joint that does not follow
// while nothing holds is a tracking fault of the controller that commands it, and a normal run
// has none.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <map>
#include <memory>
#include <numbers>
#include <optional>
#include <string>
#include <vector>

#include "cambio/config/hardware_description.hpp"
#include "cambio/config/rig_loader.hpp"
#include "cambio/config/shipped_config.hpp"
#include "cambio/control/arm_reach_loop.hpp"
#include "cambio/control/believed_joints.hpp"
#include "cambio/control/command_tracking.hpp"
#include "cambio/control/gaze_loop.hpp"
#include "cambio/control/joint_loop.hpp"
#include "cambio/control/kinematics.hpp"
#include "cambio/control/pose_hold_loop.hpp"
#include "update_heap_use.hpp"

namespace cambio::control {
namespace {

constexpr double kDeg = std::numbers::pi / 180.0;
constexpr std::int64_t kMs = 1'000'000;
constexpr int kControlEveryMs = 5;  // 200 Hz control over a 1 kHz joint loop.

// One group of the rig. Enabled joints go exactly where they are told (a stuck joint stays put,
// enabled and fault-free: a drive that does not follow and does not know it); drive states walk
// one CiA 402 transition per read(). While `fault_active`, every joint is in fault and requests
// wait; at the fault's onset the joints coast `coast_rad` on (the brakes are not the command).
class FakeGroup final : public hal::JointGroup {
 public:
  FakeGroup(const hal::HardwareInfo& hardware, const hal::JointGroupInfo& info) : info_(info) {
    for (const auto& joint : info_.joints) {
      position.push_back(hardware.find_joint(joint)->initial_position_rad);
    }
    drive.assign(info_.joints.size(), hal::DriveState::kOperationEnabled);
    pending.assign(info_.joints.size(), std::nullopt);
    stuck.assign(info_.joints.size(), 0);
  }
  const hal::JointGroupInfo& info() const override { return info_; }
  hal::Status read(std::span<hal::JointState> out, std::int64_t& stamp_ns) override {
    hal::Status status = hal::Status::kOk;
    for (std::size_t j = 0; j < out.size(); ++j) {
      if (fault_active) {
        drive[j] = hal::DriveState::kFault;
      } else if (pending[j]) {
        const hal::DriveState next = hal::next_drive_state(drive[j], *pending[j]);
        if (next == drive[j]) {
          pending[j].reset();
        } else {
          drive[j] = next;
        }
      }
      out[j] = {};
      out[j].position_rad = position[j];
      out[j].stamp_ns = now_ns;
      out[j].drive_state = drive[j];
      if (!hal::is_enabled(drive[j])) out[j].status_bits |= hal::kJointNotEnabled;
      if (hal::is_faulted(drive[j])) {
        out[j].status_bits |= hal::kJointFault;
        status = hal::Status::kFault;
      }
    }
    stamp_ns = now_ns;
    return status;
  }
  hal::Status write(std::span<const hal::JointCommand> commands) override {
    for (std::size_t j = 0; j < commands.size(); ++j) {
      if (hal::is_enabled(drive[j]) && stuck[j] == 0 &&
          commands[j].mode == hal::CommandMode::kPosition) {
        position[j] = commands[j].value;
      }
    }
    return hal::Status::kOk;
  }
  hal::Status request(hal::DriveRequest request, int joint) override {
    for (std::size_t j = 0; j < drive.size(); ++j) {
      if (joint == kAllJoints || static_cast<std::size_t>(joint) == j) pending[j] = request;
    }
    return hal::Status::kOk;
  }
  void start_fault(double coast_rad) {
    fault_active = true;
    for (auto& q : position) q += coast_rad;
  }

  std::int64_t now_ns = 0;
  bool fault_active = false;
  std::vector<double> position;
  std::vector<hal::DriveState> drive;
  std::vector<std::optional<hal::DriveRequest>> pending;
  std::vector<std::uint8_t> stuck;

 private:
  hal::JointGroupInfo info_;
};

// The shipped rig's head and arms, a joint loop over all of them, the arm loop and the gaze loop
// wired as the run assembly wires them (the gaze loop overlays the arms' targets), stepped on one
// clock: the joint loop every millisecond, then the control loops every fifth.
class HoldRig {
 public:
  /// `pose_hold_deg`: a pose hold (these joints away from their initial positions) instead of the
  /// arm and gaze loops.
  explicit HoldRig(double max_tracking_error_rad = 0.35,
                   std::optional<std::map<std::string, double>> pose_hold_deg = std::nullopt)
      : hardware_(config::hardware_description(
            config::load_rig(config::find_shipped_config("rigs/cambio.yaml")))),
        truth_(hardware_) {
    // The reach experiment's lowered arms, grippers open 20 deg.
    const std::map<std::string, double> arm_deg{
        {"shoulder_pitch", 45}, {"elbow", 80}, {"wrist", -70}, {"gripper", 20}};
    for (auto& joint : hardware_.joints) {
      for (const auto& [suffix, deg] : arm_deg) {
        if (joint.name.ends_with(suffix)) joint.initial_position_rad = deg * kDeg;
      }
    }
    JointTargetFrame pose;
    std::vector<hal::JointGroup*> groups;
    for (const auto& info : hardware_.groups) {
      groups_.push_back(std::make_unique<FakeGroup>(hardware_, info));
      groups.push_back(groups_.back().get());
      for (const auto& joint : info.joints) {
        rig_order_.push_back(joint);
        pose.commands[static_cast<std::size_t>(pose.count++)] = {
            hal::CommandMode::kPosition, hardware_.find_joint(joint)->initial_position_rad};
      }
    }
    pose_ = pose;
    JointLoopParams joint_params;
    joint_params.command_timeout_s = 0.1;
    joint_params.feedback_timeout_s = 0.02;
    joint_params.fault_recovery_delay_s = 0.5;
    joint_params.max_fault_recoveries = 1;
    joint_loop_ = std::make_unique<JointLoop>(groups, targets_, states_, joint_params);

    max_error_tree_.assign(hardware_.joints.size(), max_tracking_error_rad);
    if (pose_hold_deg) {
      JointTargetFrame held = pose;
      for (const auto& [joint, deg] : *pose_hold_deg)
        held.commands[index(joint)].value = deg * kDeg;
      pose_ = held;
      pose_hold_ =
          std::make_unique<PoseHoldLoop>(hardware_, held, believed(), max_error_tree_, targets_);
      for (hal::Loop* loop : loops()) loop->configure();
      for (hal::Loop* loop : loops()) loop->activate();
      return;
    }
    ArmReachParams arm;
    arm.groups = {"left_arm", "right_arm"};
    arm.gain_per_s = 4.0;
    arm.max_speed_m_s = 0.6;
    arm.max_acceleration_m_s2 = 3.0;
    arm.probe_depth_m = 0.03;
    arm.arrive_tolerance_m = 0.002;
    arm.posture_gain_per_s = 2.0;
    arm.gripper_speed_rad_s = 1.5;
    arm.max_tracking_error_rad = max_error_tree_;
    arm_loop_ = std::make_unique<ArmReachLoop>(hardware_, arm, pose, believed(), &gaze_status_,
                                               arm_commands_,
                                               std::array<hal::TouchSensor*, 2>{nullptr, nullptr});

    GazeLoopParams gaze;
    gaze.fixation.dominant_eye = hal::Eye::kLeft;
    gaze.fixation.gain_per_s = 4.0;
    gaze.fixation.neck_rule_rad = 30.0 * kDeg;
    gaze.fixation.default_depth_m = 1.0;
    gaze.vergence.verging_eye = hal::Eye::kRight;
    gaze.vergence.focal_px =
        hardware_.find_camera(hardware_.stereo->right_camera)->intrinsics.focal_x_px;
    gaze.vergence.gain = 0.5;
    gaze.vergence.min_confidence = 0.3;
    gaze.vergence.max_step_rad = 3.0 * kDeg;
    gaze.pursuit_gain_per_s = 20.0;
    gaze.pursuit_lead = 1.0;
    gaze.max_tracking_error_rad = max_error_tree_;
    gaze_loop_ = std::make_unique<GazeLoop>(hardware_, gaze, pose, believed(), summaries_,
                                            ssm_requests_, gaze_commands_, targets_);
    gaze_loop_->set_overlay(&arm_loop_->targets(), arm_loop_->arm_rig_indices());

    for (hal::Loop* loop : loops()) loop->configure();
    for (hal::Loop* loop : loops()) loop->activate();
  }

  std::vector<hal::Loop*> loops() {
    if (pose_hold_) return {joint_loop_.get(), pose_hold_.get()};
    return {joint_loop_.get(), arm_loop_.get(), gaze_loop_.get()};
  }

  /// One millisecond: the joint loop, then (every fifth) the arm and gaze loops. Returns the
  /// statuses the control loops returned (kOk when they did not run).
  std::array<hal::Status, 2> step_ms() {
    for (auto& group : groups_) group->now_ns = now_ns_;
    previous_q_ = positions();
    (void)joint_loop_->update(tick(1e-3, joint_cycle_++));
    std::array<hal::Status, 2> statuses{hal::Status::kOk, hal::Status::kOk};
    if (ms_ % kControlEveryMs == 0 && pose_hold_) {
      statuses[1] = heap_use_.update(*pose_hold_, tick(kControlEveryMs * 1e-3, control_cycle_++));
    } else if (ms_ % kControlEveryMs == 0) {
      statuses[0] = heap_use_.update(*arm_loop_, tick(kControlEveryMs * 1e-3, control_cycle_));
      statuses[1] = heap_use_.update(*gaze_loop_, tick(kControlEveryMs * 1e-3, control_cycle_));
      ++control_cycle_;
      GazeStatus status;
      if (gaze_loop_->status().read(status)) gaze_status_.write(status);
    }
    ++ms_;
    now_ns_ += kMs;
    return statuses;
  }
  bool control_ran_last_step() const { return (ms_ - 1) % kControlEveryMs == 0; }

  void saccade_to(const Eigen::Vector3d& p_W) {
    GazeCommand c;
    c.sequence = ++gaze_sequence_;
    c.action = GazeAction::kSaccade;
    c.target.kind = GazeTargetKind::kPoint;
    c.target.point_W_m = {p_W.x(), p_W.y(), p_W.z()};
    c.verge = true;
    gaze_commands_.write(c);
  }
  void reach(const Eigen::Vector3d& p_W) {
    ArmCommand c;
    c.sequence = ++arm_sequence_;
    c.action = ArmAction::kReach;
    c.arm = ArmSide::kRight;
    c.target = ReachTargetKind::kPoint;
    c.point_W_m = {p_W.x(), p_W.y(), p_W.z()};
    arm_commands_.write(c);
  }
  /// What the SSM would say with the eyes held still on a surface the verging eye sees
  /// `disparity_px` off: published as a new frame.
  void publish_disparity(double disparity_px) {
    perception::SsmSummary summary;
    summary.sequence = ++frames_;
    summary.stamp_ns = now_ns_;
    summary.disparity.valid = true;
    summary.disparity.confidence = 0.9f;
    summary.disparity.disparity_px = static_cast<float>(disparity_px);
    summaries_.write(summary);
  }

  /// A joint that stays where it is, enabled and fault-free, whatever it is sent.
  void stick(const std::string& joint) {
    for (auto& group : groups_) {
      const auto& joints = group->info().joints;
      const auto it = std::find(joints.begin(), joints.end(), joint);
      if (it != joints.end()) group->stuck[static_cast<std::size_t>(it - joints.begin())] = 1;
    }
  }
  FakeGroup& group(const std::string& name) {
    for (auto& group : groups_) {
      if (group->info().name == name) return *group;
    }
    throw std::out_of_range(name);
  }
  /// Every joint's drive position, rig order.
  std::vector<double> positions() const {
    std::vector<double> q;
    for (const auto& group : groups_)
      q.insert(q.end(), group->position.begin(), group->position.end());
    return q;
  }
  const std::vector<double>& previous_positions() const { return previous_q_; }
  /// The targets the gaze loop published last (every joint, rig order: what the joint loop reads).
  JointTargetFrame targets() const {
    JointTargetFrame frame;
    EXPECT_TRUE(targets_.read(frame));
    return frame;
  }
  JointTargetFrame arm_targets() const {
    JointTargetFrame frame;
    EXPECT_TRUE(arm_loop_->targets().read(frame));
    return frame;
  }
  /// The joint loop's newest published states (what the controllers read).
  JointStateFrame states() const {
    JointStateFrame frame;
    EXPECT_TRUE(states_.read(frame));
    return frame;
  }
  GazeStatus gaze_status() const {
    GazeStatus s;
    EXPECT_TRUE(gaze_loop_->status().read(s));
    return s;
  }
  ArmStatus arm_status() const {
    ArmStatus s;
    EXPECT_TRUE(arm_loop_->status().read(s));
    return s;
  }
  std::size_t index(const std::string& joint) const {
    return static_cast<std::size_t>(std::find(rig_order_.begin(), rig_order_.end(), joint) -
                                    rig_order_.begin());
  }
  std::vector<std::size_t> indices_of(const std::string& group_name) const {
    std::vector<std::size_t> out;
    for (const auto& info : hardware_.groups) {
      if (info.name != group_name) continue;
      for (const auto& joint : info.joints) out.push_back(index(joint));
    }
    return out;
  }
  double max_velocity(std::size_t rig) const {
    return hardware_.find_joint(rig_order_[rig])->limits.max_velocity_rad_s;
  }
  /// Angle between the left eye's optical axis and the ray to `p_W` at the drives' positions.
  double left_gaze_error_deg(const Eigen::Vector3d& p_W) {
    EXPECT_EQ(truth_.update_rig_order(positions()), hal::Status::kOk);
    const Eigen::Isometry3d X_WC = truth_.X_WF(truth_.frame_index(hardware_.stereo->left_camera));
    const Eigen::Vector3d ray = p_W - X_WC.translation();
    const Eigen::Vector3d axis = X_WC.linear().col(2);
    return std::atan2(axis.cross(ray).norm(), axis.dot(ray)) / kDeg;
  }
  const ArmChain& right_arm() const { return *arm_loop_->arm(1); }
  JointLoop& joint_loop() { return *joint_loop_; }
  GazeLoop& gaze_loop() { return *gaze_loop_; }
  PoseHoldLoop& pose_hold() { return *pose_hold_; }
  ArmReachLoop& arm_loop() { return *arm_loop_; }
  const UpdateHeapUse& heap_use() const { return heap_use_; }
  std::int64_t ms() const { return ms_; }
  const std::vector<std::string>& rig_order() const { return rig_order_; }
  const hal::HardwareInfo& hardware() const { return hardware_; }
  const JointTargetFrame& pose() const { return pose_; }
  std::vector<double> max_error_tree() const { return max_error_tree_; }

 private:
  BelievedJoints believed() {
    std::vector<int> all(rig_order_.size());
    for (std::size_t i = 0; i < all.size(); ++i) all[i] = static_cast<int>(i);
    return BelievedJoints({{&states_, all}}, static_cast<int>(rig_order_.size()));
  }
  hal::LoopTick tick(double period_s, std::uint64_t cycle) const {
    hal::LoopTick t;
    t.cycle = cycle;
    t.now_ns = now_ns_;
    t.deadline_ns = now_ns_;
    t.period_s = period_s;
    return t;
  }

  hal::HardwareInfo hardware_;
  Kinematics truth_;
  std::vector<std::unique_ptr<FakeGroup>> groups_;
  std::vector<std::string> rig_order_;
  JointTargetFrame pose_;
  std::vector<double> max_error_tree_;
  hal::SeqlockChannel<JointTargetFrame> targets_;
  hal::SeqlockChannel<JointStateFrame> states_;
  hal::SeqlockChannel<perception::SsmSummary> summaries_;
  hal::SeqlockChannel<perception::SsmRequest> ssm_requests_;
  hal::SeqlockChannel<GazeCommand> gaze_commands_;
  hal::SeqlockChannel<GazeStatus> gaze_status_;
  hal::SeqlockChannel<ArmCommand> arm_commands_;
  std::unique_ptr<JointLoop> joint_loop_;
  std::unique_ptr<ArmReachLoop> arm_loop_;
  std::unique_ptr<GazeLoop> gaze_loop_;
  std::unique_ptr<PoseHoldLoop> pose_hold_;
  UpdateHeapUse heap_use_;
  std::vector<double> previous_q_;
  std::int64_t now_ns_ = 1'000'000'000;
  std::int64_t ms_ = 0;
  std::uint64_t joint_cycle_ = 0;
  std::uint64_t control_cycle_ = 0;
  std::uint64_t gaze_sequence_ = 0;
  std::uint64_t arm_sequence_ = 0;
  std::uint64_t frames_ = 0;
};

// 22 deg to the left of the head at eye height, 1 m ahead; the reach's target in front of the
// right shoulder.
const Eigen::Vector3d kGazeTarget(1.0, 0.45, 1.40);
const Eigen::Vector3d kReachTarget(0.45, -0.15, 1.05);

double max_abs_difference(const JointTargetFrame& a, const JointTargetFrame& b,
                          const std::vector<std::size_t>& joints) {
  double d = 0.0;
  for (const std::size_t j : joints)
    d = std::max(d, std::abs(a.commands[j].value - b.commands[j].value));
  return d;
}
double max_abs_difference(const JointTargetFrame& command, const std::vector<double>& q,
                          const std::vector<std::size_t>& joints) {
  double d = 0.0;
  for (const std::size_t j : joints) d = std::max(d, std::abs(command.commands[j].value - q[j]));
  return d;
}

bool all_enabled(const JointStateFrame& states, const std::vector<std::size_t>& joints) {
  return std::all_of(joints.begin(), joints.end(), [&](std::size_t j) {
    return (states.states[j].status_bits & hal::kJointNotEnabled) == 0;
  });
}

TEST(HoldRecovery, AHoldMidSaccadeAndMidReachFreezesTheCommandsAndRestartsFromTheMeasuredPose) {
  HoldRig rig;
  const auto head = rig.indices_of("head");
  const auto right_arm = rig.indices_of("right_arm");
  std::vector<std::size_t> every(rig.rig_order().size());
  for (std::size_t j = 0; j < every.size(); ++j) every[j] = j;

  // The right arm reaches from 0.1 s; at 0.5 s a saccade; 30 ms into it the head's drives fault.
  while (rig.ms() < 100) rig.step_ms();
  rig.reach(kReachTarget);
  while (rig.ms() < 500) rig.step_ms();
  rig.saccade_to(kGazeTarget);
  while (rig.ms() < 530) rig.step_ms();
  ASSERT_TRUE(rig.gaze_status().saccade_active);
  ASSERT_EQ(rig.arm_status().arms[1].phase, ReachPhase::kReaching);
  rig.group("head").start_fault(0.01);

  // Held: while the joint loop holds, the frame says so; the commands must not move. The eyes
  // are still, so the SSM keeps reporting the same disparity: a controller that integrated it
  // would wind the verging eye up.
  rig.step_ms();
  ASSERT_TRUE(rig.states().holding);
  const JointTargetFrame at_hold = rig.targets();
  const JointTargetFrame arm_at_hold = rig.arm_targets();
  const double vergence_at_hold_rad = rig.gaze_status().vergence_rad;
  double gaze_drift_rad = 0.0;
  double arm_drift_rad = 0.0;
  int held_ms = 0;
  while (rig.ms() < 1530) {
    if (rig.ms() % 33 == 0) rig.publish_disparity(25.0);
    rig.step_ms();
    ++held_ms;
    gaze_drift_rad = std::max(gaze_drift_rad, max_abs_difference(rig.targets(), at_hold, head));
    arm_drift_rad =
        std::max(arm_drift_rad, max_abs_difference(rig.arm_targets(), arm_at_hold, right_arm));
  }
  const JointTargetFrame at_end_of_hold = rig.targets();
  const double command_vs_measured_rad = max_abs_difference(at_end_of_hold, rig.positions(), head);
  const double arm_command_vs_measured_rad =
      max_abs_difference(at_end_of_hold, rig.positions(), right_arm);
  std::printf(
      "[ figures  ] after a %d ms hold: gaze command drift %.4f deg, head command vs measured "
      "%.4f deg, vergence %.4f -> %.4f deg; arm command drift %.4f deg, arm command vs measured "
      "%.4f deg\n",
      held_ms, gaze_drift_rad / kDeg, command_vs_measured_rad / kDeg, vergence_at_hold_rad / kDeg,
      rig.gaze_status().vergence_rad / kDeg, arm_drift_rad / kDeg,
      arm_command_vs_measured_rad / kDeg);
  EXPECT_EQ(gaze_drift_rad, 0.0);
  EXPECT_EQ(arm_drift_rad, 0.0);
  EXPECT_EQ(rig.gaze_status().vergence_rad, vergence_at_hold_rad);

  // The drives come back (the joint loop resets them and enables them where they stand): the
  // first command after the hold is the measured pose. Each controller restarts once its own
  // joints are driven: the arm while the head's drives are still enabling.
  rig.group("head").fault_active = false;
  std::array<bool, 2> restarted{};  // Head, right arm.
  const std::array<const std::vector<std::size_t>*, 2> joints_of{&head, &right_arm};
  double fastest_ratio = 0.0;
  while (rig.ms() < 4500) {
    rig.step_ms();
    const JointStateFrame states = rig.states();
    for (std::size_t c = 0; c < 2; ++c) {
      if (restarted[c] || !rig.control_ran_last_step() || states.holding ||
          !all_enabled(states, *joints_of[c])) {
        continue;
      }
      restarted[c] = true;
      const JointTargetFrame first = rig.targets();
      for (const std::size_t j : *joints_of[c]) {
        EXPECT_EQ(first.commands[j].value, states.states[j].position_rad) << rig.rig_order()[j];
      }
    }
    for (const std::size_t j : every) {
      const double speed = std::abs(rig.positions()[j] - rig.previous_positions()[j]) / 1e-3;
      fastest_ratio = std::max(fastest_ratio, speed / rig.max_velocity(j));
    }
  }
  EXPECT_TRUE(restarted[0] && restarted[1]);
  EXPECT_LE(fastest_ratio, 1.0 + 1e-9);
  EXPECT_EQ(rig.joint_loop().fault_recoveries(), 1u);
  // And both motions still end where they were going.
  EXPECT_LT(rig.left_gaze_error_deg(kGazeTarget), 0.2);
  EXPECT_EQ(rig.arm_status().arms[1].phase, ReachPhase::kArrived);
  // No tracking fault in a run whose joints follow: the commands led them by a cycle's motion.
  EXPECT_EQ(rig.gaze_loop().fault_count(), 0u);
  EXPECT_EQ(rig.arm_loop().fault_count(), 0u);
  for (const CommandTracking* tracking :
       {&rig.gaze_loop().tracking(), &rig.arm_loop().tracking()}) {
    const TrackingReport report = tracking->report();
    EXPECT_FALSE(report.faulted) << report.fault;
    EXPECT_GT(report.peak_error_rad, 0.0) << report.controller;
    EXPECT_LT(report.peak_error_rad, 0.1) << report.controller << ": " << report.peak_joint;
    EXPECT_EQ(report.restarts, 1u) << report.controller;
    EXPECT_GT(report.frozen_cycles, 190u) << report.controller;  // A second at 200 Hz.
  }
  EXPECT_EQ(rig.heap_use().allocations, 0u);
}

TEST(HoldRecovery, AnEyeThatDoesNotFollowIsATrackingFaultOfTheGazeLoopWhichThenHolds) {
  HoldRig rig(0.2);
  rig.stick("left_eye_pan");
  while (rig.ms() < 100) rig.step_ms();
  rig.saccade_to(kGazeTarget);
  const auto head = rig.indices_of("head");
  hal::Status gaze = hal::Status::kOk;
  while (rig.ms() < 600 && gaze == hal::Status::kOk) gaze = rig.step_ms()[1];
  ASSERT_EQ(gaze, hal::Status::kFault);
  EXPECT_NE(rig.gaze_loop().fault_message().find("left_eye_pan"), std::string::npos)
      << rig.gaze_loop().fault_message();
  EXPECT_NE(rig.gaze_loop().fault_message().find("beyond its max_tracking_error of 0.200 rad"),
            std::string::npos)
      << rig.gaze_loop().fault_message();
  EXPECT_TRUE(rig.gaze_status().tracking_fault);
  // Faulted at the first cycle beyond the limit: the eye had not moved, so the command was
  // within one cycle's motion of 0.2 rad.
  const TrackingReport report = rig.gaze_loop().tracking().report();
  EXPECT_TRUE(report.faulted);
  EXPECT_GT(report.peak_error_rad, 0.2);
  EXPECT_LT(report.peak_error_rad, 0.2 + 8.0 * 0.005 + 1e-9);

  // It holds where the joints are, refuses what it is told, and keeps saying kFault.
  for (int i = 0; i < 200; ++i) {
    const hal::Status status = rig.step_ms()[1];
    if (rig.control_ran_last_step()) {
      EXPECT_EQ(status, hal::Status::kFault);
    }
  }
  EXPECT_LT(max_abs_difference(rig.targets(), rig.positions(), head), 1e-12);
  rig.saccade_to(Eigen::Vector3d(1.0, -0.45, 1.40));
  for (int i = 0; i < 20; ++i) rig.step_ms();
  EXPECT_EQ(rig.gaze_status().last_refusal, GazeRefusal::kTrackingFault);
  EXPECT_LT(max_abs_difference(rig.targets(), rig.positions(), head), 1e-12);
  EXPECT_EQ(rig.gaze_loop().fault_count(), 1u);
  EXPECT_EQ(rig.arm_loop().fault_count(), 0u);
}

TEST(HoldRecovery, AnElbowThatDoesNotFollowIsATrackingFaultOfTheArmLoopWhichStopsTheReach) {
  HoldRig rig(0.1);
  rig.stick("right_elbow");
  while (rig.ms() < 100) rig.step_ms();
  rig.reach(kReachTarget);
  hal::Status arm = hal::Status::kOk;
  while (rig.ms() < 3000 && arm == hal::Status::kOk) arm = rig.step_ms()[0];
  ASSERT_EQ(arm, hal::Status::kFault);
  EXPECT_NE(rig.arm_loop().fault_message().find("right_elbow"), std::string::npos)
      << rig.arm_loop().fault_message();
  const ArmStatus status = rig.arm_status();
  EXPECT_TRUE(status.tracking_fault);
  EXPECT_EQ(status.arms[1].phase, ReachPhase::kIdle);
  for (int i = 0; i < 100; ++i) rig.step_ms();
  EXPECT_LT(max_abs_difference(rig.targets(), rig.positions(), rig.indices_of("right_arm")), 1e-12);
  EXPECT_EQ(rig.gaze_loop().fault_count(), 0u);
}

TEST(HoldRecovery, APoseHoldFreezesWhileHeldThenGoesBackToItsPoseFromWhereTheJointsAre) {
  // The neck on its way to 40 deg when the head faults for a second.
  HoldRig rig(0.35, std::map<std::string, double>{{"neck_pan", 40.0}});
  const auto head = rig.indices_of("head");
  const std::size_t neck = rig.index("neck_pan");
  while (rig.ms() < 100) rig.step_ms();
  ASSERT_GT(rig.positions()[neck], 0.1);
  ASSERT_LT(rig.positions()[neck], 0.6);
  rig.group("head").start_fault(0.01);
  rig.step_ms();
  const JointTargetFrame at_hold = rig.targets();
  while (rig.ms() < 1100) {
    rig.step_ms();
    ASSERT_EQ(max_abs_difference(rig.targets(), at_hold, head), 0.0);
  }
  rig.group("head").fault_active = false;
  bool restarted = false;
  double fastest_ratio = 0.0;
  while (rig.ms() < 2000) {
    rig.step_ms();
    const JointStateFrame states = rig.states();
    if (!restarted && rig.control_ran_last_step() && !states.holding && all_enabled(states, head)) {
      restarted = true;
      for (const std::size_t j : head) {
        EXPECT_EQ(rig.targets().commands[j].value, states.states[j].position_rad);
      }
    }
    for (const std::size_t j : head) {
      const double speed = std::abs(rig.positions()[j] - rig.previous_positions()[j]) / 1e-3;
      fastest_ratio = std::max(fastest_ratio, speed / rig.max_velocity(j));
    }
  }
  EXPECT_TRUE(restarted);
  EXPECT_LE(fastest_ratio, 1.0 + 1e-9);
  EXPECT_NEAR(rig.positions()[neck], 40.0 * kDeg, 1e-12);
  EXPECT_EQ(rig.pose_hold().fault_count(), 0u);
  EXPECT_EQ(rig.pose_hold().tracking().restarts(), 1u);
  EXPECT_EQ(rig.heap_use().allocations, 0u);
}

}  // namespace
}  // namespace cambio::control

namespace cambio::control {
namespace {

// The guard itself, on frames written by hand: a brief stale hold with the drives enabled (late
// feedback on a loaded bus) resumes from the command, keeping the servo's lead; a longer hold, or
// one during which a drive was not enabled, restarts from the measured pose.
TEST(CommandTrackingGuard, ABriefStaleHoldResumesALongOneOrALostDriveRestarts) {
  hal::SeqlockChannel<JointStateFrame> states;
  BelievedJoints believed({{&states, {0}}}, 1);
  CommandTracking tracking("gaze", {{"left_eye_pan", 0, 0, 0.3}});
  std::array<double, 1> q{};
  const auto step = [&](bool holding, std::uint32_t bits) {
    JointStateFrame frame;
    frame.count = 1;
    frame.holding = holding;
    frame.states[0].status_bits = bits;
    states.write(frame);
    believed.read(q);
    return tracking.step(believed);
  };
  using Step = CommandTracking::Step;
  ASSERT_EQ(step(false, 0), Step::kFollow);
  for (int i = 0; i < 2; ++i) EXPECT_EQ(step(true, hal::kJointStale), Step::kFrozen);
  EXPECT_EQ(step(false, 0), Step::kFollow) << "a 2-cycle stale hold";
  EXPECT_EQ(tracking.restarts(), 0u);

  for (int i = 0; i < 20; ++i) EXPECT_EQ(step(true, hal::kJointStale), Step::kFrozen);
  EXPECT_EQ(step(false, 0), Step::kRestart) << "a 20-cycle stale hold";

  EXPECT_EQ(step(true, hal::kJointStale), Step::kFrozen);
  EXPECT_EQ(step(true, hal::kJointNotEnabled), Step::kFrozen);
  EXPECT_EQ(step(false, 0), Step::kRestart) << "a brief hold during which the drive was disabled";
  EXPECT_EQ(tracking.restarts(), 2u);
  EXPECT_EQ(tracking.frozen_cycles(), 24u);
}

}  // namespace
}  // namespace cambio::control
