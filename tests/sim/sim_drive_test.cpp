// The sim's CiA 402 drives: lifecycle, quick stop, injected faults, lost and frozen feedback.
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "cambio/hal/manual_clock.hpp"
#include "cambio/sim/sim_backend.hpp"
#include "sim_test_support.hpp"

namespace cambio::sim {
namespace {

using hal::DriveRequest;
using hal::DriveState;

constexpr std::int64_t kStepNs = 1'000'000;  // The shipped rig's physics step.
constexpr double kStepS = 1e-3;

/// The shipped rig without noise (so a joint at rest is exactly still) in an empty world, with
/// the head (kinematic joints) and the left arm (physics joints) made, stepped by hand.
class SimDriveTest : public ::testing::Test {
 protected:
  void SetUp() override {
    rig_ = testing::load_shipped_rig();
    testing::make_ideal(rig_);
    backend_ = testing::make_sim(rig_, testing::empty_scene(), clock_);
    head_ = backend_->make_joint_group("head");
    arm_ = backend_->make_joint_group("left_arm");
    backend_->configure();
    backend_->activate();
  }

  /// Physics steps at the next milliseconds, the run's clock moving with them.
  void step(int count = 1) {
    for (int k = 0; k < count; ++k) {
      t_ns_ += kStepNs;
      clock_.advance_to_ns(t_ns_);
      ASSERT_EQ(backend_->physics().step_once(t_ns_), hal::Status::kOk);
    }
  }

  std::vector<hal::JointState> read(hal::JointGroup& group, hal::Status* status = nullptr,
                                    std::int64_t* stamp_ns = nullptr) {
    std::vector<hal::JointState> states(group.info().joints.size());
    std::int64_t stamp = 0;
    const hal::Status result = group.read(states, stamp);
    if (status != nullptr) *status = result;
    if (stamp_ns != nullptr) *stamp_ns = stamp;
    return states;
  }

  /// True joint positions (rad), in the group's order.
  std::vector<double> truth(const hal::JointGroup& group) {
    std::vector<double> q;
    for (const auto& name : group.info().joints) {
      q.push_back(backend_->ground_truth().joint_position_rad(name));
    }
    return q;
  }

  void write_positions(hal::JointGroup& group, const std::vector<double>& positions_rad,
                       double effort_feedforward_nm = 0.0, std::size_t feedforward_joint = 0) {
    std::vector<hal::JointCommand> commands(positions_rad.size());
    for (std::size_t k = 0; k < commands.size(); ++k) commands[k].value = positions_rad[k];
    commands[feedforward_joint].effort_feedforward_nm = effort_feedforward_nm;
    ASSERT_EQ(group.write(commands), hal::Status::kOk);
  }

  /// Targets `offset_rad` away from every joint's current true position, within its limits.
  std::vector<double> far_targets(const hal::JointGroup& group, double offset_rad) {
    std::vector<double> targets = truth(group);
    for (std::size_t k = 0; k < targets.size(); ++k) {
      const auto& limits = group.info().limits[k];
      targets[k] =
          std::clamp(targets[k] + offset_rad, limits.min_position_rad, limits.max_position_rad);
    }
    return targets;
  }

  /// Requests kEnable and steps until every joint of `group` is operation enabled; returns the
  /// steps it took (fails after 10).
  int enable(hal::JointGroup& group) {
    EXPECT_EQ(group.request(DriveRequest::kEnable), hal::Status::kOk);
    for (int steps = 1; steps <= 10; ++steps) {
      step();
      const auto states = read(group);
      if (std::all_of(states.begin(), states.end(), [](const hal::JointState& state) {
            return state.drive_state == DriveState::kOperationEnabled;
          })) {
        return steps;
      }
    }
    ADD_FAILURE() << group.info().name << " did not reach operation enabled";
    return -1;
  }

  double max_acceleration(const hal::JointGroup& group, std::size_t k) const {
    return group.info().limits[k].max_acceleration_rad_s2;
  }

  config::RigConfig rig_;
  hal::ManualClock clock_;
  std::unique_ptr<SimBackend> backend_;
  std::unique_ptr<hal::JointGroup> head_;
  std::unique_ptr<hal::JointGroup> arm_;
  std::int64_t t_ns_ = 0;
};

TEST_F(SimDriveTest, StartsSwitchOnDisabledAndDoesNotFollowCommands) {
  hal::Status status = hal::Status::kFault;
  for (auto* group : {head_.get(), arm_.get()}) {
    for (const auto& state : read(*group, &status)) {
      EXPECT_EQ(state.drive_state, DriveState::kSwitchOnDisabled);
      EXPECT_TRUE(state.status_bits & hal::kJointNotEnabled);
      EXPECT_FALSE(state.status_bits & hal::kJointFault);
      EXPECT_EQ(state.error_code, 0);
    }
    EXPECT_EQ(status, hal::Status::kOk);
  }
  const auto head_start = truth(*head_);
  const auto arm_start = truth(*arm_);
  write_positions(*head_, far_targets(*head_, 0.3));
  write_positions(*arm_, far_targets(*arm_, 0.3));
  step(500);
  EXPECT_EQ(truth(*head_), head_start) << "a disabled head joint stays exactly where it is";
  const auto arm_now = truth(*arm_);
  for (std::size_t k = 0; k < arm_now.size(); ++k) {
    EXPECT_NEAR(arm_now[k], arm_start[k], 1e-3) << arm_->info().joints[k] << " holds, disabled";
  }
  for (const auto& state : read(*head_)) {
    EXPECT_EQ(state.drive_state, DriveState::kSwitchOnDisabled) << "nothing was requested";
  }
}

TEST_F(SimDriveTest, EnableWalksTheStateMachineAndHoldsTheMeasuredPositionNotAnOldTarget) {
  const auto start = truth(*head_);
  // A far target written while disabled, and again during the walk: never executed.
  const auto far = far_targets(*head_, 0.4);
  write_positions(*head_, far);
  step(5);
  ASSERT_EQ(head_->request(DriveRequest::kEnable), hal::Status::kOk);
  const DriveState walk[] = {DriveState::kReadyToSwitchOn, DriveState::kSwitchedOn,
                             DriveState::kOperationEnabled};
  for (const DriveState expected : walk) {
    write_positions(*head_, far);
    step();
    for (const auto& state : read(*head_)) EXPECT_EQ(state.drive_state, expected);
  }
  for (const auto& state : read(*head_)) {
    EXPECT_FALSE(state.status_bits & hal::kJointNotEnabled);
  }
  step(500);
  EXPECT_EQ(truth(*head_), start) << "enabling never jumps to a target written before it";
  // Targets written once enabled are followed.
  const auto target = far_targets(*head_, 0.1);
  write_positions(*head_, target);
  step(1'000);
  const auto now = truth(*head_);
  for (std::size_t k = 0; k < now.size(); ++k) {
    EXPECT_NEAR(now[k], target[k], 1e-9) << head_->info().joints[k];
  }
  // The arm too, through physics.
  EXPECT_LE(enable(*arm_), 3);
  const auto arm_target = far_targets(*arm_, 0.2);
  write_positions(*arm_, arm_target);
  step(2'000);
  const auto arm_now = truth(*arm_);
  for (std::size_t k = 0; k < arm_now.size(); ++k) {
    EXPECT_NEAR(arm_now[k], arm_target[k], 5e-3) << arm_->info().joints[k];
  }
}

TEST_F(SimDriveTest, DisableBrakesWithinTheAccelerationLimitAndStopsFollowing) {
  ASSERT_GT(enable(*head_), 0);
  write_positions(*head_, far_targets(*head_, 0.5));
  step(60);  // neck_pan cruises at its 2 rad/s after 0.1 s; the eyes are already there.
  ASSERT_EQ(head_->request(DriveRequest::kDisable), hal::Status::kOk);
  std::vector<std::vector<double>> trajectory{truth(*head_)};
  step();
  for (const auto& state : read(*head_))
    EXPECT_EQ(state.drive_state, DriveState::kSwitchOnDisabled);
  for (int k = 0; k < 300; ++k) {
    write_positions(*head_, far_targets(*head_, -0.5));  // Ignored.
    trajectory.push_back(truth(*head_));
    step();
  }
  trajectory.push_back(truth(*head_));
  for (std::size_t j = 0; j < trajectory.front().size(); ++j) {
    for (std::size_t k = 2; k < trajectory.size(); ++k) {
      const double a =
          (trajectory[k][j] - 2 * trajectory[k - 1][j] + trajectory[k - 2][j]) / (kStepS * kStepS);
      ASSERT_LE(std::abs(a), max_acceleration(*head_, j) * (1 + 1e-6))
          << head_->info().joints[j] << " step " << k;
    }
    EXPECT_EQ(trajectory.back()[j], trajectory[trajectory.size() - 100][j])
        << head_->info().joints[j] << " came to rest and holds";
  }
  EXPECT_NE(trajectory[1][0], trajectory.back()[0]) << "neck_pan was moving when disabled";
}

TEST_F(SimDriveTest, QuickStopBrakesWithinTheAccelerationLimitHoldsAndReEnablesInPlace) {
  ASSERT_GT(enable(*head_), 0);
  write_positions(*head_, far_targets(*head_, 0.8));
  step(150);
  const std::size_t neck_pan = 0;
  ASSERT_EQ(head_->info().joints[neck_pan], "neck_pan");
  ASSERT_NEAR(read(*head_)[neck_pan].velocity_rad_s, 2.0, 0.05) << "cruising";
  ASSERT_EQ(head_->request(DriveRequest::kQuickStop), hal::Status::kOk);
  std::vector<double> q{truth(*head_)[neck_pan]};
  int steps_to_rest = -1;
  for (int k = 0; k < 400; ++k) {
    write_positions(*head_, far_targets(*head_, 0.8));  // Ignored while quick stopped.
    step();
    q.push_back(truth(*head_)[neck_pan]);
    EXPECT_EQ(read(*head_)[neck_pan].drive_state, DriveState::kQuickStopActive);
    if (steps_to_rest < 0 && k > 0 && q[q.size() - 1] == q[q.size() - 2]) steps_to_rest = k;
  }
  for (std::size_t k = 2; k < q.size(); ++k) {
    const double a = (q[k] - 2 * q[k - 1] + q[k - 2]) / (kStepS * kStepS);
    ASSERT_LE(std::abs(a), max_acceleration(*head_, neck_pan) * (1 + 1e-6)) << "step " << k;
  }
  // 2 rad/s at 20 rad/s^2: 0.1 s, 0.1 rad.
  EXPECT_NEAR(steps_to_rest, 100, 2);
  EXPECT_NEAR(q.back() - q.front(), 0.1, 5e-3);
  // Enable from quick stop (transition 16): holds where it stopped, then follows again.
  ASSERT_EQ(head_->request(DriveRequest::kEnable), hal::Status::kOk);
  step();
  EXPECT_EQ(read(*head_)[neck_pan].drive_state, DriveState::kOperationEnabled);
  step(200);
  EXPECT_EQ(truth(*head_)[neck_pan], q.back());
  write_positions(*head_, far_targets(*head_, -0.05));
  step(500);
  EXPECT_NEAR(truth(*head_)[neck_pan], q.back() - 0.05, 1e-9);
}

TEST_F(SimDriveTest, InjectedFaultLatchesUntilResetAndReEnablesAtTheMeasuredPosition) {
  ASSERT_GT(enable(*head_), 0);
  const std::size_t neck_pan = 0;
  write_positions(*head_, far_targets(*head_, 0.5));
  step(60);
  backend_->inject_fault("neck_pan", 0x7300);
  step();
  hal::Status status = hal::Status::kOk;
  auto states = read(*head_, &status);
  EXPECT_EQ(status, hal::Status::kFault);
  EXPECT_EQ(states[neck_pan].drive_state, DriveState::kFaultReactionActive);
  EXPECT_EQ(states[neck_pan].error_code, 0x7300);
  EXPECT_TRUE(states[neck_pan].status_bits & hal::kJointFault);
  EXPECT_TRUE(states[neck_pan].status_bits & hal::kJointNotEnabled);
  for (std::size_t k = 1; k < states.size(); ++k) {
    EXPECT_EQ(states[k].drive_state, DriveState::kOperationEnabled) << "only neck_pan faulted";
    EXPECT_FALSE(states[k].status_bits & hal::kJointFault);
  }
  // The fault reaction brakes; the drive then latches kFault and nothing moves it.
  std::vector<double> q{truth(*head_)[neck_pan]};
  for (int k = 0; k < 200; ++k) {
    step();
    q.push_back(truth(*head_)[neck_pan]);
  }
  for (std::size_t k = 2; k < q.size(); ++k) {
    const double a = (q[k] - 2 * q[k - 1] + q[k - 2]) / (kStepS * kStepS);
    ASSERT_LE(std::abs(a), max_acceleration(*head_, neck_pan) * (1 + 1e-6)) << "step " << k;
  }
  EXPECT_EQ(read(*head_)[neck_pan].drive_state, DriveState::kFault);
  const double stopped = truth(*head_)[neck_pan];
  ASSERT_EQ(head_->request(DriveRequest::kEnable, 0), hal::Status::kOk);  // Needs a reset first.
  for (int k = 0; k < 300; ++k) {
    write_positions(*head_, far_targets(*head_, -0.5));
    step();
  }
  states = read(*head_, &status);
  EXPECT_EQ(status, hal::Status::kFault);
  EXPECT_EQ(states[neck_pan].drive_state, DriveState::kFault);
  EXPECT_EQ(states[neck_pan].error_code, 0x7300) << "kept until a reset";
  EXPECT_EQ(truth(*head_)[neck_pan], stopped) << "a faulted drive does not move";

  // Fault reset: switch-on disabled, error cleared; re-enabled separately, where it stands.
  ASSERT_EQ(head_->request(DriveRequest::kFaultReset, 0), hal::Status::kOk);
  step();
  states = read(*head_, &status);
  EXPECT_EQ(status, hal::Status::kOk);
  EXPECT_EQ(states[neck_pan].drive_state, DriveState::kSwitchOnDisabled);
  EXPECT_EQ(states[neck_pan].error_code, 0);
  EXPECT_FALSE(states[neck_pan].status_bits & hal::kJointFault);
  EXPECT_TRUE(states[neck_pan].status_bits & hal::kJointNotEnabled);
  step(10);
  EXPECT_EQ(read(*head_)[neck_pan].drive_state, DriveState::kSwitchOnDisabled)
      << "a reset does not re-enable";

  // A new fault latches again, though a reset was the last request.
  backend_->inject_fault("neck_pan", 0x8611);
  step(10);
  states = read(*head_);
  EXPECT_EQ(states[neck_pan].drive_state, DriveState::kFault);
  EXPECT_EQ(states[neck_pan].error_code, 0x8611);
  ASSERT_EQ(head_->request(DriveRequest::kFaultReset, 0), hal::Status::kOk);
  step();
  ASSERT_EQ(read(*head_)[neck_pan].drive_state, DriveState::kSwitchOnDisabled);

  ASSERT_EQ(head_->request(DriveRequest::kEnable, 0), hal::Status::kOk);
  step(3);
  EXPECT_EQ(read(*head_)[neck_pan].drive_state, DriveState::kOperationEnabled);
  step(300);
  EXPECT_EQ(truth(*head_)[neck_pan], stopped) << "re-enabled at the measured position";
}

TEST_F(SimDriveTest, AFaultedArmHoldsItsPoseUnderGravity) {
  ASSERT_GT(enable(*arm_), 0);
  auto target = truth(*arm_);
  target[1] = 0.4;  // Shoulder pitch: the arm forwards, where gravity pulls hardest.
  write_positions(*arm_, target);
  step(2'000);
  backend_->inject_fault("left_shoulder_pitch", 0x2310);
  step(5);
  hal::Status status = hal::Status::kOk;
  EXPECT_EQ(read(*arm_, &status)[1].drive_state, DriveState::kFault);
  EXPECT_EQ(status, hal::Status::kFault);
  const auto held = truth(*arm_);
  step(2'000);
  const auto now = truth(*arm_);
  for (std::size_t k = 0; k < now.size(); ++k) {
    EXPECT_NEAR(now[k], held[k], 1e-3) << arm_->info().joints[k];
  }
}

TEST(SimArmDriveTest, ADisabledArmHoldsWhereItIsAndStopsPushing) {
  auto rig = testing::load_shipped_rig();
  testing::make_ideal(rig);
  hal::ManualClock clock;
  auto backend = testing::make_sim(
      rig,
      config::load_scene_from_string(
          "objects:\n"
          "  - {name: table_top, shape: box, size_m: [0.6, 1.0, 0.04], xyz_m: [0.6, 0, 0.78]}\n",
          "bare_table.yaml"),
      clock);
  auto arm = backend->make_joint_group("left_arm");
  auto hand = backend->make_touch_sensor("left_hand");
  backend->configure();
  backend->activate();
  std::int64_t t_ns = 0;
  auto step = [&](int count) {
    for (int k = 0; k < count; ++k) {
      ASSERT_EQ(backend->physics().step_once(t_ns += kStepNs), hal::Status::kOk);
    }
  };
  auto drive_state = [&] {
    std::vector<hal::JointState> states(arm->info().joints.size());
    std::int64_t stamp = 0;
    (void)arm->read(states, stamp);
    return states[1].drive_state;
  };
  ASSERT_EQ(arm->request(DriveRequest::kEnable), hal::Status::kOk);
  step(3);
  ASSERT_EQ(drive_state(), DriveState::kOperationEnabled);
  // Shoulder pitch down, well into the table top (a straight arm meets it at about 0.42 rad).
  std::vector<hal::JointCommand> commands(arm->info().joints.size());
  commands[1].value = 0.7;
  ASSERT_EQ(arm->write(commands), hal::Status::kOk);
  step(2'500);
  hal::TouchReading pressing;
  ASSERT_EQ(hand->read(pressing), hal::Status::kOk);
  ASSERT_TRUE(pressing.in_contact);
  ASSERT_GT(pressing.normal_force_n, 1.0);
  const double pitch = backend->ground_truth().joint_position_rad("left_shoulder_pitch");

  ASSERT_EQ(arm->request(DriveRequest::kDisable), hal::Status::kOk);
  step(1'000);
  ASSERT_EQ(drive_state(), DriveState::kSwitchOnDisabled);
  hal::TouchReading held;
  ASSERT_EQ(hand->read(held), hal::Status::kOk);
  EXPECT_LT(held.normal_force_n, 0.2 * pressing.normal_force_n)
      << "held at the measured position, not pushing on to the old target";
  EXPECT_NEAR(backend->ground_truth().joint_position_rad("left_shoulder_pitch"), pitch, 5e-3);

  // Enabled again where it is: the old 0.7 rad target is not pursued.
  ASSERT_EQ(arm->request(DriveRequest::kEnable), hal::Status::kOk);
  step(1'000);
  ASSERT_EQ(drive_state(), DriveState::kOperationEnabled);
  hal::TouchReading enabled;
  ASSERT_EQ(hand->read(enabled), hal::Status::kOk);
  EXPECT_LT(enabled.normal_force_n, 0.2 * pressing.normal_force_n);
}

TEST_F(SimDriveTest, CommLossFreezesTheReadingAndIsStickyUntilAFaultReset) {
  ASSERT_GT(enable(*head_), 0);
  const std::size_t eye_tilt = 2;
  ASSERT_EQ(head_->info().joints[eye_tilt], "eye_tilt");
  const std::int64_t before_ns = read(*head_)[eye_tilt].stamp_ns;
  backend_->inject_comm_loss("eye_tilt");
  for (int k = 0; k < 500; ++k) {
    ASSERT_EQ(head_->request(DriveRequest::kEnable), hal::Status::kOk);  // Cannot get through.
    step();
    hal::Status status = hal::Status::kOk;
    std::int64_t group_stamp = 0;
    const auto states = read(*head_, &status, &group_stamp);
    ASSERT_EQ(status, hal::Status::kFault) << "step " << k;
    ASSERT_TRUE(states[eye_tilt].status_bits & hal::kJointCommLost) << "sticky, step " << k;
    ASSERT_EQ(states[eye_tilt].stamp_ns, before_ns) << "the stamp stops advancing";
    ASSERT_EQ(states[0].stamp_ns, t_ns_) << "the other joints still answer";
    ASSERT_EQ(group_stamp, t_ns_) << "the group stamp is the newest joint's";
    ASSERT_FALSE(states[0].status_bits & hal::kJointCommLost);
  }
  ASSERT_EQ(head_->request(DriveRequest::kFaultReset, static_cast<int>(eye_tilt)),
            hal::Status::kOk);
  step();
  hal::Status status = hal::Status::kFault;
  const auto states = read(*head_, &status);
  EXPECT_EQ(status, hal::Status::kOk);
  EXPECT_FALSE(states[eye_tilt].status_bits & hal::kJointCommLost);
  EXPECT_EQ(states[eye_tilt].stamp_ns, t_ns_);
  EXPECT_EQ(states[eye_tilt].drive_state, DriveState::kSwitchOnDisabled)
      << "the drive faulted when it lost its master";
  EXPECT_EQ(states[eye_tilt].error_code, 0);
}

TEST_F(SimDriveTest, FrozenFeedbackKeepsItsStampWhileTheDriveRunsOn) {
  ASSERT_GT(enable(*head_), 0);
  const std::size_t right_eye_pan = 4;
  ASSERT_EQ(head_->info().joints[right_eye_pan], "right_eye_pan");
  const hal::JointState before = read(*head_)[right_eye_pan];
  backend_->freeze_feedback("right_eye_pan", true);
  write_positions(*head_, far_targets(*head_, 0.2));
  step(300);
  hal::Status status = hal::Status::kFault;
  auto states = read(*head_, &status);
  EXPECT_EQ(status, hal::Status::kOk) << "nothing flags it: the joint loop sees the stamp";
  EXPECT_EQ(states[right_eye_pan].stamp_ns, before.stamp_ns);
  EXPECT_EQ(states[right_eye_pan].position_rad, before.position_rad);
  EXPECT_EQ(states[right_eye_pan].status_bits & ~hal::kJointAtLimit, 0u);
  EXPECT_EQ(states[0].stamp_ns, t_ns_);
  const double moved = truth(*head_)[right_eye_pan];
  EXPECT_NEAR(moved, before.position_rad + 0.2, 1e-9) << "the drive ran on";
  backend_->freeze_feedback("right_eye_pan", false);
  step();
  states = read(*head_);
  EXPECT_EQ(states[right_eye_pan].stamp_ns, t_ns_);
  EXPECT_EQ(states[right_eye_pan].position_rad, moved);
}

TEST_F(SimDriveTest, ArmsAddTheEffortFeedForwardToTheirTorque) {
  ASSERT_GT(enable(*arm_), 0);
  auto target = truth(*arm_);
  target[2] = 0.6;  // The elbow, bent.
  write_positions(*arm_, target);
  step(2'000);
  const double without = truth(*arm_)[2];
  const double feedforward_nm = 0.5;
  write_positions(*arm_, target, feedforward_nm, 2);
  step(2'000);
  const double with = truth(*arm_)[2];
  // At rest the PD balances the extra torque: kp (reference - q) + feed-forward = 0.
  const int elbow = backend_->world().find_joint("left_elbow");
  const double kp = backend_->physics().gains()[static_cast<std::size_t>(elbow)].kp_nm_rad;
  EXPECT_NEAR(with - without, feedforward_nm / kp, 0.1 * feedforward_nm / kp);
}

TEST_F(SimDriveTest, DeactivateDisablesEveryDriveAndFaultsStayLatched) {
  ASSERT_GT(enable(*head_), 0);
  ASSERT_GT(enable(*arm_), 0);
  backend_->inject_fault("left_wrist", 0x5530);
  step();
  clock_.advance_to_ns(t_ns_ + 5 * kStepNs);
  backend_->deactivate();
  backend_->deactivate();  // Idempotent.
  for (const auto& state : read(*head_)) {
    EXPECT_EQ(state.drive_state, DriveState::kSwitchOnDisabled);
    EXPECT_EQ(state.stamp_ns, t_ns_ + 5 * kStepNs) << "stamped on the run's clock";
  }
  const auto arm = read(*arm_);
  EXPECT_EQ(arm[3].drive_state, DriveState::kFault);
  EXPECT_EQ(arm[3].error_code, 0x5530);
  EXPECT_EQ(arm[0].drive_state, DriveState::kSwitchOnDisabled);
}

TEST_F(SimDriveTest, BadRequestsAndHooksAreRefused) {
  EXPECT_EQ(head_->request(DriveRequest::kEnable, 5), hal::Status::kRejected);
  EXPECT_EQ(head_->request(DriveRequest::kEnable, -2), hal::Status::kRejected);
  EXPECT_THROW(backend_->inject_fault("no_such_joint", 0x1000), std::invalid_argument);
  EXPECT_THROW(backend_->inject_fault("neck_pan", 0), std::invalid_argument);
  EXPECT_THROW(backend_->inject_comm_loss("nope"), std::invalid_argument);
  EXPECT_THROW(backend_->freeze_feedback("nope", true), std::invalid_argument);
}

}  // namespace
}  // namespace cambio::sim
