// The fault path of the whole stack below control, without CAN: the real joint loop driving the
// sim's CiA 402 drives under the lockstep executor. A drive faults, the loop holds every joint,
// a fault reset and enable bring the drive back at its measured position, and motion resumes.
#include <gtest/gtest.h>

#include <cmath>
#include <string>
#include <vector>

#include "cambio/control/joint_loop.hpp"
#include "cambio/sim/sim_backend.hpp"
#include "lockstep_sim.hpp"

namespace cambio::sim {
namespace {

/// The control loop of the test: every cycle, the head's targets are a slow sine on neck pan
/// (rad) and the initial pose elsewhere.
class SineTargets final : public hal::Loop {
 public:
  SineTargets(hal::SeqlockChannel<control::JointTargetFrame>& out, int joints, int moving)
      : out_(out), moving_(moving) {
    frame_.count = joints;
  }
  const std::string& name() const override { return name_; }
  hal::Status update(const hal::LoopTick& tick) noexcept override {
    frame_.stamp_ns = tick.now_ns;
    frame_.commands[static_cast<std::size_t>(moving_)].value =
        0.3 * std::sin(2.0 * static_cast<double>(tick.now_ns) * 1e-9);
    out_.write(frame_);
    return hal::Status::kOk;
  }

 private:
  std::string name_ = "control";
  hal::SeqlockChannel<control::JointTargetFrame>& out_;
  control::JointTargetFrame frame_{};
  int moving_;
};

struct Stack {
  Stack() : rig(make_rig()), sim(rig, testing::empty_scene()) {
    head = sim.backend->make_joint_group("head");
    joint_loop = std::make_unique<control::JointLoop>(std::vector<hal::JointGroup*>{head.get()},
                                                      targets, states, control::JointLoopParams{});
    control = std::make_unique<SineTargets>(targets, 5, 0);
    sim.add_loop(*joint_loop, 1000.0);
    sim.add_loop(*control, 200.0);
    sim.start();
  }
  static config::RigConfig make_rig() {
    auto rig = testing::load_shipped_rig();
    testing::make_ideal(rig);
    for (auto& joint : rig.joints) joint.initial_position_rad = 0.0;
    return rig;
  }
  control::JointStateFrame published() {
    control::JointStateFrame frame;
    EXPECT_TRUE(states.read(frame));
    return frame;
  }
  double true_neck_pan() { return sim.backend->ground_truth().joint_position_rad("neck_pan"); }

  config::RigConfig rig;
  testing::LockstepSim sim;
  std::unique_ptr<hal::JointGroup> head;
  hal::SeqlockChannel<control::JointTargetFrame> targets;
  hal::SeqlockChannel<control::JointStateFrame> states;
  std::unique_ptr<control::JointLoop> joint_loop;
  std::unique_ptr<SineTargets> control;
};

TEST(JointLoopOnSim, AFaultHoldsEveryJointUntilResetThenMotionResumesWithoutAJump) {
  Stack stack;
  stack.sim.run_for_s(0.5);
  ASSERT_EQ(stack.published().states[0].drive_state, hal::DriveState::kOperationEnabled)
      << "the joint loop enabled the drives";
  EXPECT_GT(std::abs(stack.true_neck_pan()), 0.05) << "the neck follows the sine";

  // Eye tilt faults. The faulted drive brakes; every other joint holds: the neck stops
  // following its sine.
  stack.sim.backend->inject_fault("eye_tilt", 0x5530);
  stack.sim.run_for_s(0.2);
  const double held = stack.true_neck_pan();
  stack.sim.run_for_s(0.5);
  EXPECT_NEAR(stack.true_neck_pan(), held, 1e-9) << "the neck moved while a fault was latched";
  control::JointStateFrame frame = stack.published();
  EXPECT_TRUE(frame.fault_latched);
  EXPECT_EQ(frame.states[2].drive_state, hal::DriveState::kFault);
  EXPECT_EQ(frame.states[2].error_code, 0x5530);
  EXPECT_NE(frame.states[2].status_bits & hal::kJointFault, 0u);
  EXPECT_GT(stack.joint_loop->fault_hold_cycles(), 500u);

  // Reset and enable: the latch clears, eye tilt comes back where it stands, the neck moves on.
  const double eye_tilt_before = stack.sim.backend->ground_truth().joint_position_rad("eye_tilt");
  stack.joint_loop->request(hal::DriveRequest::kFaultReset);
  stack.joint_loop->request(hal::DriveRequest::kEnable);
  stack.sim.run_for_s(0.05);
  frame = stack.published();
  EXPECT_FALSE(frame.fault_latched);
  EXPECT_EQ(frame.states[2].drive_state, hal::DriveState::kOperationEnabled);
  EXPECT_EQ(frame.states[2].error_code, 0);
  EXPECT_NEAR(stack.sim.backend->ground_truth().joint_position_rad("eye_tilt"), eye_tilt_before,
              1e-9)
      << "re-enabling moved the joint: its first target was not its measured position";
  stack.sim.run_for_s(0.3);
  EXPECT_GT(std::abs(stack.true_neck_pan() - held), 0.01) << "motion resumed";
  stack.sim.stop();
}

TEST(JointLoopOnSim, FrozenFeedbackHoldsWithoutLatchingAndLostContactLatches) {
  Stack stack;
  stack.sim.run_for_s(0.3);
  stack.sim.backend->freeze_feedback("left_eye_pan", true);
  stack.sim.run_for_s(0.1);
  const double held = stack.true_neck_pan();
  stack.sim.run_for_s(0.2);
  EXPECT_NEAR(stack.true_neck_pan(), held, 1e-9) << "moved on stale feedback";
  control::JointStateFrame frame = stack.published();
  EXPECT_TRUE(frame.holding);
  EXPECT_FALSE(frame.fault_latched);
  EXPECT_NE(frame.states[3].status_bits & hal::kJointStale, 0u);

  stack.sim.backend->freeze_feedback("left_eye_pan", false);
  stack.sim.run_for_s(0.2);
  EXPECT_GT(std::abs(stack.true_neck_pan() - held), 0.01) << "fresh feedback: motion resumes";

  stack.sim.backend->inject_comm_loss("right_eye_pan");
  stack.sim.run_for_s(0.1);
  const double lost_at = stack.true_neck_pan();
  stack.sim.run_for_s(0.3);
  EXPECT_NEAR(stack.true_neck_pan(), lost_at, 1e-9);
  frame = stack.published();
  EXPECT_TRUE(frame.fault_latched);
  EXPECT_NE(frame.states[4].status_bits & hal::kJointCommLost, 0u);
  stack.sim.stop();
}

}  // namespace
}  // namespace cambio::sim
