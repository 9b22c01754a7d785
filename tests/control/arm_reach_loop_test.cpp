// The arm loop closed around ideal arms: the joints reach what is commanded each cycle (the
// sim's servo model, contacts and rendering are the reach experiment's business), the touch
// sensor is a fake the test fires. What is checked against the closed-form fingertips
// (fingertips_W, itself held to the general kinematics in arm_reach_check_test): the servo
// moves the fingertips along a straight line, slowing near the target, within the speed cap and
// the joints' limits; a touch stops it and closes the gripper; refusals say why; the nearer arm
// reaches; update() never allocates, reaching or not.
#include "cambio/control/arm_reach_loop.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <map>
#include <memory>
#include <numbers>
#include <string>
#include <vector>

#include "cambio/config/hardware_description.hpp"
#include "cambio/config/rig_loader.hpp"
#include "cambio/config/shipped_config.hpp"
#include "update_heap_use.hpp"

namespace cambio::control {
namespace {

constexpr double kDeg = std::numbers::pi / 180.0;
constexpr double kPeriodS = 0.005;

class FakeTouch final : public hal::TouchSensor {
 public:
  const std::string& name() const override { return name_; }
  hal::Status read(hal::TouchReading& out) override {
    out = hal::TouchReading{};
    out.in_contact = in_contact;
    return hal::Status::kOk;
  }
  bool in_contact = false;

 private:
  std::string name_ = "fake";
};

class ArmHarness {
 public:
  explicit ArmHarness(double approach_m = 0.0, bool with_gaze = true,
                      bool with_touch_sensors = true)
      : hardware_(config::hardware_description(
            config::load_rig(config::find_shipped_config("rigs/cambio.yaml")))) {
    if (!with_touch_sensors) hardware_.touch_sensors.clear();
    for (const auto& group : hardware_.groups) {
      for (const auto& joint : group.joints) rig_order_.push_back(joint);
    }
    // The reach experiment's lowered arms, grippers open 20 deg.
    const std::map<std::string, double> initial_deg{
        {"shoulder_pitch", 45}, {"elbow", 80}, {"wrist", -70}, {"gripper", 20}};
    JointTargetFrame pose;
    for (const auto& name : rig_order_) {
      double q = 0.0;
      for (const auto& [suffix, deg] : initial_deg) {
        if (name.ends_with(suffix) && name.find("eye") == std::string::npos) {
          q = deg * kDeg;
        }
      }
      pose.commands[static_cast<std::size_t>(pose.count++)] = {hal::CommandMode::kPosition, q};
      q_rig_.push_back(q);
    }
    publish_states();
    params_.groups = {"left_arm", "right_arm"};
    params_.gain_per_s = 4.0;
    params_.max_speed_m_s = 0.6;
    params_.max_acceleration_m_s2 = 3.0;
    params_.probe_depth_m = 0.03;
    params_.approach_m = approach_m;
    params_.arrive_tolerance_m = 0.002;
    params_.posture_gain_per_s = 2.0;
    params_.gripper_speed_rad_s = 1.5;
    std::vector<int> all(rig_order_.size());
    for (std::size_t i = 0; i < all.size(); ++i) all[i] = static_cast<int>(i);
    BelievedJoints believed({{&states_, all}}, static_cast<int>(rig_order_.size()));
    loop_ = std::make_unique<ArmReachLoop>(
        hardware_, params_, pose, std::move(believed), with_gaze ? &gaze_ : nullptr, commands_,
        std::array<hal::TouchSensor*, 2>{&touch_[0], &touch_[1]});
    loop_->set_trajectories(&trajectories_);
    loop_->configure();
    loop_->activate();
  }

  /// A trajectory of rig joints through `points` (each: time, then one position per joint, rad),
  /// positions only.
  void follow(const std::vector<int>& rig_joints, const std::vector<std::vector<double>>& points) {
    JointTrajectory trajectory;
    trajectory.sequence = ++trajectory_sequence_;
    trajectory.joint_count = static_cast<int>(rig_joints.size());
    trajectory.point_count = static_cast<int>(points.size());
    for (std::size_t j = 0; j < rig_joints.size(); ++j)
      trajectory.joint_rig_index[j] = rig_joints[j];
    for (std::size_t k = 0; k < points.size(); ++k) {
      trajectory.time_from_start_s[k] = points[k][0];
      for (std::size_t j = 0; j < rig_joints.size(); ++j)
        trajectory.positions_rad[k][j] = points[k][j + 1];
    }
    trajectories_.write(trajectory);
  }

  void command(ArmAction action, ArmSide side = ArmSide::kNearest,
               ReachTargetKind kind = ReachTargetKind::kPoint,
               const Eigen::Vector3d& p = Eigen::Vector3d::Zero()) {
    ArmCommand c;
    c.sequence = ++sequence_;
    c.action = action;
    c.arm = side;
    c.target = kind;
    c.point_W_m = {p.x(), p.y(), p.z()};
    commands_.write(c);
  }
  void move_joint(int rig_index, double position_rad) {
    ArmCommand c;
    c.sequence = ++sequence_;
    c.action = ArmAction::kMoveJoint;
    c.joint_rig_index = rig_index;
    c.position_rad = position_rad;
    commands_.write(c);
  }
  void fixation(bool valid, const Eigen::Vector3d& p = Eigen::Vector3d::Zero()) {
    GazeStatus status;
    status.believed_fixation_valid = valid;
    status.believed_fixation_W_m = {p.x(), p.y(), p.z()};
    gaze_.write(status);
  }

  void step() {
    hal::LoopTick tick;
    tick.cycle = cycle_++;
    tick.now_ns = now_ns_;
    tick.deadline_ns = now_ns_;
    tick.period_s = kPeriodS;
    ASSERT_EQ(heap_use_.update(*loop_, tick), hal::Status::kOk);
    JointTargetFrame targets;
    ASSERT_TRUE(loop_->targets().read(targets));
    for (int i = 0; i < targets.count; ++i)
      q_rig_[static_cast<std::size_t>(i)] = targets.commands[static_cast<std::size_t>(i)].value;
    publish_states();  // Ideal joints: where they were commanded.
    now_ns_ += static_cast<std::int64_t>(kPeriodS * 1e9);
  }

  ArmStatus status() const {
    ArmStatus s;
    (void)loop_->status().read(s);
    return s;
  }
  const ArmChain& arm(int side) const { return *loop_->arm(side); }
  std::array<double, 4> q_arm(int side) const {
    std::array<double, 4> q{};
    for (std::size_t k = 0; k < 4; ++k) q[k] = q_rig_[static_cast<std::size_t>(arm(side).rig[k])];
    return q;
  }
  double opening(int side) const { return q_rig_[static_cast<std::size_t>(arm(side).rig[4])]; }
  /// The fingertips' midpoint at the commanded joints, in closed form.
  Eigen::Vector3d tip(int side) const {
    return fingertips_W(arm(side), opening(side), q_arm(side));
  }
  FakeTouch& touch(int side) { return touch_[static_cast<std::size_t>(side)]; }
  std::int64_t now_ns() const { return now_ns_; }
  ArmReachLoop& loop() { return *loop_; }
  /// What the loop's update() took from the heap over every step() so far.
  const UpdateHeapUse& heap_use() const { return heap_use_; }

 private:
  void publish_states() {
    JointStateFrame frame;
    frame.count = static_cast<int>(q_rig_.size());
    for (std::size_t i = 0; i < q_rig_.size(); ++i) {
      frame.states[i].position_rad = q_rig_[i];
      frame.states[i].stamp_ns = now_ns_;
    }
    frame.stamp_ns = now_ns_;
    states_.write(frame);
  }

  hal::HardwareInfo hardware_;
  std::vector<std::string> rig_order_;
  std::vector<double> q_rig_;
  ArmReachParams params_;
  hal::SeqlockChannel<JointStateFrame> states_;
  hal::SeqlockChannel<GazeStatus> gaze_;
  hal::SeqlockChannel<ArmCommand> commands_;
  hal::SeqlockChannel<JointTrajectory> trajectories_;
  std::uint64_t trajectory_sequence_ = 0;
  std::array<FakeTouch, 2> touch_;
  std::unique_ptr<ArmReachLoop> loop_;
  std::uint64_t sequence_ = 0;
  std::uint64_t cycle_ = 1;
  std::int64_t now_ns_ = 1'000'000'000;
  UpdateHeapUse heap_use_;
};

// In front of the right shoulder, a little right and up from the lowered hand.
const Eigen::Vector3d kRightTarget(0.45, -0.15, 1.05);

TEST(ArmReachLoop, ServoesTheFingertipsAlongAStraightLineAndArrives) {
  ArmHarness arm;  // No approach: straight from where the hand is.
  arm.step();
  const Eigen::Vector3d start = arm.tip(1);
  arm.command(ArmAction::kReach, ArmSide::kNearest, ReachTargetKind::kPoint, kRightTarget);
  const Eigen::Vector3d direction = (kRightTarget - start).normalized();
  const Eigen::Vector3d aim = kRightTarget + 0.03 * direction;
  double worst_off_line_m = 0.0, top_speed = 0.0, speed_near_end = 0.0;
  Eigen::Vector3d previous = start;
  int cycles = 0;
  for (; cycles < 1000 && arm.status().arms[1].phase != ReachPhase::kArrived; ++cycles) {
    arm.step();
    const Eigen::Vector3d tip = arm.tip(1);
    const Eigen::Vector3d along = start + direction * direction.dot(tip - start);
    worst_off_line_m = std::max(worst_off_line_m, (tip - along).norm());
    const double speed = (tip - previous).norm() / kPeriodS;
    top_speed = std::max(top_speed, speed);
    if ((aim - tip).norm() < 0.01) speed_near_end = std::max(speed_near_end, speed);
    previous = tip;
    for (std::size_t k = 0; k < 4; ++k) {
      const hal::JointLimits& limits = arm.arm(1).limits[k];
      ASSERT_GE(arm.q_arm(1)[k], limits.min_position_rad - 1e-12);
      ASSERT_LE(arm.q_arm(1)[k], limits.max_position_rad + 1e-12);
    }
  }
  const ArmStatus status = arm.status();
  ASSERT_EQ(status.arms[1].phase, ReachPhase::kArrived) << "after " << cycles << " cycles";
  EXPECT_EQ(status.arms[0].phase, ReachPhase::kIdle) << "the nearer arm reaches, alone";
  EXPECT_LT((arm.tip(1) - aim).norm(), 0.002);
  // The law is q' = lambda J^+ e: the fingertips move on the line (Euler steps bend it a little).
  EXPECT_LT(worst_off_line_m, 0.003);
  // The cap holds on the law's linear velocity; the steps' chords differ from it at second order.
  EXPECT_LE(top_speed, 0.6 * 1.01);
  EXPECT_GT(top_speed, 0.3);
  EXPECT_LT(speed_near_end, 4.0 * 0.01 * 1.05) << "gain x distance: slow near the target";
  EXPECT_LT(cycles * kPeriodS, 2.5);
  for (int i = 0; i < 3; ++i) {
    EXPECT_DOUBLE_EQ(status.arms[1].target_W_m[static_cast<std::size_t>(i)], kRightTarget[i]);
    EXPECT_NEAR(status.arms[1].gripper_W_m[static_cast<std::size_t>(i)], arm.tip(1)[i], 1e-9);
  }
  EXPECT_NEAR(status.arms[1].distance_to_target_m, 0.03, 0.003);
}

TEST(ArmReachLoop, GoesInHeadOnFromInFrontOfTheTarget) {
  ArmHarness arm(0.08);
  arm.command(ArmAction::kReach, ArmSide::kRight, ReachTargetKind::kPoint, kRightTarget);
  Eigen::Vector3d in = kRightTarget - arm.arm(1).shoulder_W;
  in.z() = 0.0;
  in.normalize();
  // Once past the approach point, the fingertips stay on the horizontal line into the target.
  bool went_in = false;
  double worst_off_line_m = 0.0;
  for (int cycle = 0; cycle < 1000; ++cycle) {
    arm.step();
    if (arm.status().arms[1].phase != ReachPhase::kReaching) break;
    const Eigen::Vector3d from_target = arm.tip(1) - kRightTarget;
    if (from_target.dot(in) > -0.04) {
      went_in = true;
      worst_off_line_m =
          std::max(worst_off_line_m, (from_target - in * in.dot(from_target)).norm());
    }
  }
  EXPECT_TRUE(went_in);
  EXPECT_EQ(arm.status().arms[1].phase, ReachPhase::kArrived);
  EXPECT_LT(worst_off_line_m, 0.02);
  EXPECT_LT((arm.tip(1) - (kRightTarget + 0.03 * in)).norm(), 0.002);
}

TEST(ArmReachLoop, TouchStopsTheArmThenTheGripperCloses) {
  ArmHarness arm(0.08);
  arm.step();
  const std::int64_t command_ns = arm.now_ns();
  arm.command(ArmAction::kReach, ArmSide::kNearest, ReachTargetKind::kPoint, kRightTarget);
  // A surface 1 cm short of the target: the estimate put it a little too far.
  int cycles = 0;
  for (; cycles < 1000; ++cycles) {
    arm.touch(1).in_contact = arm.tip(1).x() >= kRightTarget.x() - 0.01;
    arm.step();
    if (arm.status().arms[1].phase != ReachPhase::kReaching) break;
  }
  ArmStatus status = arm.status();
  ASSERT_EQ(status.arms[1].phase, ReachPhase::kTouching);
  EXPECT_GE(status.arms[1].touch_ns, command_ns);
  EXPECT_EQ(status.arms[1].command_ns, command_ns);
  EXPECT_NEAR(arm.tip(1).x(), kRightTarget.x() - 0.01, 0.002) << "stopped where it touched";
  const std::array<double, 4> stopped = arm.q_arm(1);
  EXPECT_FALSE(status.arms[1].gripper_closed);
  const double open = arm.opening(1);
  for (int i = 0; i < 100; ++i) arm.step();  // 0.5 s: 20 deg at 1.5 rad/s takes 0.23 s.
  status = arm.status();
  EXPECT_EQ(status.arms[1].phase, ReachPhase::kTouching);
  EXPECT_EQ(arm.q_arm(1), stopped) << "the arm holds while the gripper closes";
  EXPECT_LT(arm.opening(1), open);
  EXPECT_DOUBLE_EQ(arm.opening(1), arm.arm(1).limits[4].min_position_rad);
  EXPECT_TRUE(status.arms[1].gripper_closed);
  // Release opens it again, to its limit.
  arm.command(ArmAction::kRelease, ArmSide::kRight);
  for (int i = 0; i < 200; ++i) arm.step();
  EXPECT_FALSE(arm.status().arms[1].gripper_closed);
  EXPECT_DOUBLE_EQ(arm.opening(1), arm.arm(1).limits[4].max_position_rad);
}

TEST(ArmReachLoop, ReachesWhatTheHeadFixatesWithTheNearerArm) {
  ArmHarness arm;
  const Eigen::Vector3d fixated(0.45, 0.12, 1.05);  // Left of the middle: the left arm.
  arm.fixation(true, fixated);
  arm.command(ArmAction::kReach, ArmSide::kNearest, ReachTargetKind::kFixation);
  arm.step();
  const ArmStatus status = arm.status();
  EXPECT_EQ(status.arms[0].phase, ReachPhase::kReaching);
  EXPECT_EQ(status.arms[1].phase, ReachPhase::kIdle);
  for (int i = 0; i < 3; ++i) {
    EXPECT_DOUBLE_EQ(status.arms[0].target_W_m[static_cast<std::size_t>(i)], fixated[i]);
  }
}

TEST(ArmReachLoop, AnArmWithoutATouchSensorOnItsGripperIsRefusedAtConstruction) {
  try {
    ArmHarness arm(0.0, true, false);
    FAIL() << "expected std::invalid_argument";
  } catch (const std::invalid_argument& error) {
    EXPECT_NE(std::string(error.what())
                  .find("arm 'left_arm': no touch sensor on its gripper "
                        "'left_gripper'"),
              std::string::npos)
        << error.what();
  }
}

TEST(ArmReachLoop, RefusesWithoutAFixation) {
  ArmHarness arm;
  arm.fixation(false);
  arm.command(ArmAction::kReach, ArmSide::kRight, ReachTargetKind::kFixation);
  arm.step();
  EXPECT_EQ(arm.status().arms[1].phase, ReachPhase::kRefused);
  EXPECT_EQ(arm.status().refusal(), "no fixation: the eyes' axes do not meet in front of them");
  ArmHarness blind(0.0, false);
  blind.command(ArmAction::kReach, ArmSide::kLeft, ReachTargetKind::kFixation);
  blind.step();
  EXPECT_EQ(blind.status().arms[0].phase, ReachPhase::kRefused);
  EXPECT_EQ(blind.status().refusal(), "no fixation: the arms have no gaze loop to ask");
}

TEST(ArmReachLoop, RefusesOutOfReachAndBeyondALimitBeforeMoving) {
  ArmHarness arm;
  arm.step();
  const std::array<double, 4> left_before = arm.q_arm(0), right_before = arm.q_arm(1);
  arm.command(ArmAction::kReach, ArmSide::kNearest, ReachTargetKind::kPoint,
              Eigen::Vector3d(1.2, -0.2, 1.05));
  arm.step();
  ArmStatus status = arm.status();
  EXPECT_EQ(status.arms[1].phase, ReachPhase::kRefused);
  EXPECT_EQ(status.arms[0].phase, ReachPhase::kIdle) << "the other arm could not either";
  EXPECT_NE(status.refusal().find("out of reach: the target is 1.200 m from right_arm's "
                                  "shoulder, the arm reaches"),
            std::string::npos)
      << status.refusal();
  // The left arm told to reach far right: its yaw.
  arm.command(ArmAction::kReach, ArmSide::kLeft, ReachTargetKind::kPoint,
              Eigen::Vector3d(0.1, -0.4, 1.05));
  arm.step();
  status = arm.status();
  EXPECT_EQ(status.arms[0].phase, ReachPhase::kRefused);
  EXPECT_NE(status.refusal().find("beyond a joint limit: left_shoulder_yaw would need"),
            std::string::npos)
      << status.refusal();
  for (int i = 0; i < 20; ++i) arm.step();
  EXPECT_EQ(arm.q_arm(0), left_before);
  EXPECT_EQ(arm.q_arm(1), right_before);
}

TEST(ArmReachLoop, NearestFallsBackToTheOtherArmWithoutARefusal) {
  ArmHarness arm;
  // Nearer the left shoulder, but beyond the left arm's limits (check_reach says which); the
  // right arm can take it: it does, and the nearer arm's refusal is not reported.
  const Eigen::Vector3d target(0.2, 0.04, 1.2);
  ASSERT_LT((target - arm.arm(0).shoulder_W).norm(), (target - arm.arm(1).shoulder_W).norm());
  ASSERT_FALSE(check_reach(arm.arm(0), 20.0 * kDeg, target, {}).reachable);
  arm.command(ArmAction::kReach, ArmSide::kNearest, ReachTargetKind::kPoint, target);
  arm.step();
  const ArmStatus status = arm.status();
  EXPECT_EQ(status.arms[0].phase, ReachPhase::kIdle);
  EXPECT_EQ(status.arms[1].phase, ReachPhase::kReaching);
  EXPECT_EQ(status.refusal(), "");
}

TEST(ArmReachLoop, MovesOneJointClampedToItsLimit) {
  ArmHarness arm;
  const int elbow = arm.arm(1).rig[2];
  arm.move_joint(elbow, 10.0);
  for (int i = 0; i < 400; ++i) arm.step();
  EXPECT_DOUBLE_EQ(arm.q_arm(1)[2], arm.arm(1).limits[2].max_position_rad);
  arm.move_joint(0, 0.3);  // The neck: not the arms'.
  arm.step();
  EXPECT_EQ(arm.status().refusal(), "move joint: rig joint 0 is not an arm joint");
}

TEST(ArmReachLoop, AJointTrajectoryMovesTheArmLinearlyThroughItsPointsAndStopsItsReach) {
  ArmHarness arm;
  arm.step();
  // A reach under way is stopped by a trajectory for that arm's joints.
  arm.command(ArmAction::kReach, ArmSide::kRight, ReachTargetKind::kPoint, kRightTarget);
  for (int i = 0; i < 10; ++i) arm.step();
  EXPECT_EQ(arm.status().arms[1].phase, ReachPhase::kReaching);
  const std::array<double, 4> q0 = arm.q_arm(1);
  const int shoulder = arm.arm(1).rig[1];
  const int elbow = arm.arm(1).rig[2];
  const int gripper = arm.arm(1).rig[4];
  const double opening0 = arm.opening(1);
  // Elbow to 1.2 rad by 0.5 s, then 1.0 by 1.5 s; the gripper to 0.1 rad by 1.5 s; linear.
  arm.follow({elbow, gripper}, {{0.5, 1.2, 0.1 + (opening0 - 0.1) * 2.0 / 3.0}, {1.5, 1.0, 0.1}});
  for (int i = 1; i <= 301; ++i) {
    arm.step();
    const double t = (i - 1) * kPeriodS;
    const double elbow_rad = t <= 0.5 ? q0[2] + (1.2 - q0[2]) * t / 0.5 : 1.2 - 0.2 * (t - 0.5);
    EXPECT_NEAR(arm.q_arm(1)[2], elbow_rad, 1e-9) << t;
    EXPECT_NEAR(arm.opening(1), opening0 + (0.1 - opening0) * t / 1.5, 1e-9) << t;
    EXPECT_EQ(arm.q_arm(1)[1], q0[1]);  // Not named: held (the reach stopped).
  }
  EXPECT_NE(arm.status().arms[1].phase, ReachPhase::kReaching);
  for (int i = 0; i < 100; ++i) arm.step();  // Held at the last point, the gripper too.
  EXPECT_NEAR(arm.q_arm(1)[2], 1.0, 1e-9);
  EXPECT_NEAR(arm.opening(1), 0.1, 1e-9);
  EXPECT_EQ(arm.loop().trajectory_follower().finished(), 1u);
  // A head joint in an arm trajectory: refused, naming it; nothing moves.
  arm.follow({shoulder, 0}, {{1.0, 0.5, 0.3}});
  arm.step();
  EXPECT_EQ(arm.status().refusal(), "joint trajectory: rig joint 0 is not an arm joint");
  EXPECT_EQ(arm.q_arm(1)[1], q0[1]);
  EXPECT_EQ(arm.heap_use().allocations, 0u);
}

TEST(ArmReachLoop, UpdateNeverAllocatesReachingOrNot) {
  // Idle, a refusal (formatted into the status's fixed buffer), a whole reach with its approach
  // (the servo's law each cycle, its secondary task and joint-limit avoidance), a joint move,
  // the gripper, a touch. The counter sees malloc as well as operator new: vpServo's matrices,
  // which this loop used to run, called malloc about 130 times per cycle.
  ArmHarness arm(0.08);
  for (int i = 0; i < 200; ++i) arm.step();
  arm.command(ArmAction::kReach, ArmSide::kNearest, ReachTargetKind::kPoint,
              Eigen::Vector3d(1.2, -0.2, 1.05));
  arm.step();
  EXPECT_EQ(arm.status().arms[1].phase, ReachPhase::kRefused);
  arm.command(ArmAction::kReach, ArmSide::kRight, ReachTargetKind::kPoint, kRightTarget);
  int reaching_cycles = 0;
  for (int i = 0; i < 1000; ++i) {
    arm.step();
    if (arm.status().arms[1].phase != ReachPhase::kReaching) break;
    ++reaching_cycles;
  }
  EXPECT_EQ(arm.status().arms[1].phase, ReachPhase::kArrived);
  EXPECT_GT(reaching_cycles, 50);
  arm.move_joint(arm.arm(0).rig[2], 1.0);
  for (int i = 0; i < 100; ++i) arm.step();
  arm.command(ArmAction::kGrasp);
  for (int i = 0; i < 100; ++i) arm.step();
  arm.command(ArmAction::kReach, ArmSide::kRight, ReachTargetKind::kPoint, kRightTarget);
  arm.touch(1).in_contact = true;
  for (int i = 0; i < 200; ++i) arm.step();
  EXPECT_EQ(arm.status().arms[1].phase, ReachPhase::kTouching);

  EXPECT_EQ(arm.heap_use().allocations, 0u);
  EXPECT_EQ(arm.heap_use().frees, 0u);
}

}  // namespace
}  // namespace cambio::control
