// The HAL's joint vocabulary: the CiA 402 drive state machine, command clamping, status
// severity and the tap that lets another thread follow a group.
#include "cambio/hal/joint_group.hpp"

#include <gtest/gtest.h>

#include <thread>

#include "cambio/hal/joint_state_tap.hpp"

namespace cambio::hal {
namespace {

DriveState walk(DriveState state, DriveRequest request, int* steps = nullptr) {
  int n = 0;
  for (DriveState next = next_drive_state(state, request); next != state;
       next = next_drive_state(state, request)) {
    state = next;
    ++n;
  }
  if (steps != nullptr) *steps = n;
  return state;
}

TEST(DriveState, EnableWalksTheCiA402PathFromSwitchOnDisabled) {
  // CiA 402-2 transitions 2, 3, 4: shutdown, switch on, enable operation.
  EXPECT_EQ(next_drive_state(DriveState::kSwitchOnDisabled, DriveRequest::kEnable),
            DriveState::kReadyToSwitchOn);
  EXPECT_EQ(next_drive_state(DriveState::kReadyToSwitchOn, DriveRequest::kEnable),
            DriveState::kSwitchedOn);
  EXPECT_EQ(next_drive_state(DriveState::kSwitchedOn, DriveRequest::kEnable),
            DriveState::kOperationEnabled);
  int steps = 0;
  EXPECT_EQ(walk(DriveState::kSwitchOnDisabled, DriveRequest::kEnable, &steps),
            DriveState::kOperationEnabled);
  EXPECT_EQ(steps, 3);
  // Transition 16: quick stop active back to operation enabled.
  EXPECT_EQ(next_drive_state(DriveState::kQuickStopActive, DriveRequest::kEnable),
            DriveState::kOperationEnabled);
}

TEST(DriveState, AFaultNeedsAResetBeforeAnythingElse) {
  for (const auto request :
       {DriveRequest::kEnable, DriveRequest::kDisable, DriveRequest::kQuickStop}) {
    EXPECT_EQ(next_drive_state(DriveState::kFault, request), DriveState::kFault)
        << to_string(request);
  }
  EXPECT_EQ(next_drive_state(DriveState::kFault, DriveRequest::kFaultReset),
            DriveState::kSwitchOnDisabled);  // Transition 15.
  EXPECT_EQ(next_drive_state(DriveState::kFaultReactionActive, DriveRequest::kFaultReset),
            DriveState::kFaultReactionActive)
      << "a reset is only accepted once the reaction has ended in fault";
  EXPECT_EQ(next_drive_state(DriveState::kNotReadyToSwitchOn, DriveRequest::kEnable),
            DriveState::kNotReadyToSwitchOn)
      << "a booting drive accepts nothing";
}

TEST(DriveState, QuickStopOnlyFromOperationEnabledAndDisableFromAnyPoweredState) {
  EXPECT_EQ(next_drive_state(DriveState::kOperationEnabled, DriveRequest::kQuickStop),
            DriveState::kQuickStopActive);
  EXPECT_EQ(next_drive_state(DriveState::kSwitchedOn, DriveRequest::kQuickStop),
            DriveState::kSwitchedOn);
  for (const auto state : {DriveState::kReadyToSwitchOn, DriveState::kSwitchedOn,
                           DriveState::kOperationEnabled, DriveState::kQuickStopActive}) {
    EXPECT_EQ(next_drive_state(state, DriveRequest::kDisable), DriveState::kSwitchOnDisabled)
        << to_string(state);
  }
  EXPECT_TRUE(is_enabled(DriveState::kOperationEnabled));
  EXPECT_FALSE(is_enabled(DriveState::kQuickStopActive));
  EXPECT_TRUE(is_faulted(DriveState::kFaultReactionActive));
}

TEST(ClampCommand, ClampsTargetsAndFeedForwardAndHoldsOnNonFiniteTargets) {
  const JointLimits limits{-1.0, 1.0, 2.0, 10.0, 3.0};
  JointCommand command{CommandMode::kPosition, 1.5, 5.0, -7.0};
  EXPECT_TRUE(clamp_command(command, limits));
  EXPECT_EQ(command.value, 1.0);
  EXPECT_EQ(command.velocity_feedforward_rad_s, 2.0);
  EXPECT_EQ(command.effort_feedforward_nm, -3.0);

  JointCommand within{CommandMode::kVelocity, -1.5, 0.0, 1.0};
  EXPECT_FALSE(clamp_command(within, limits));
  EXPECT_EQ(within.value, -1.5);

  JointCommand nan_feedforward{CommandMode::kPosition, 0.5, std::nan(""), 0.0};
  EXPECT_TRUE(clamp_command(nan_feedforward, limits));
  EXPECT_EQ(nan_feedforward.velocity_feedforward_rad_s, 0.0);

  JointCommand nan_target{CommandMode::kPosition, std::nan(""), 1.0, 1.0};
  EXPECT_TRUE(clamp_command(nan_target, limits));
  EXPECT_EQ(nan_target.mode, CommandMode::kVelocity);
  EXPECT_EQ(nan_target.value, 0.0);
  EXPECT_EQ(nan_target.effort_feedforward_nm, 0.0);

  JointCommand unlimited_effort{CommandMode::kPosition, 0.0, 0.0, 100.0};
  EXPECT_FALSE(clamp_command(unlimited_effort, JointLimits{-1.0, 1.0, 2.0, 10.0, 0.0}))
      << "max_effort 0 means the stack does not limit effort";
}

TEST(Status, WorstIsTheMostSevereWhateverTheOrder) {
  const Status ordered[] = {Status::kOk, Status::kNoNewData, Status::kStale, Status::kRejected,
                            Status::kFault};
  for (std::size_t a = 0; a < 5; ++a) {
    for (std::size_t b = 0; b < 5; ++b) {
      EXPECT_EQ(worst(ordered[a], ordered[b]), ordered[std::max(a, b)]);
    }
  }
}

class CountingGroup final : public JointGroup {
 public:
  CountingGroup() {
    info_.name = "head";
    info_.joints = {"pan", "tilt"};
    info_.limits.resize(2);
  }
  const JointGroupInfo& info() const override { return info_; }
  Status read(std::span<JointState> out, std::int64_t& stamp_ns) override {
    ++reads;
    for (auto& state : out) state.position_rad = static_cast<double>(reads);
    stamp_ns = reads;
    return Status::kOk;
  }
  Status write(std::span<const JointCommand>) override { return Status::kOk; }
  Status request(DriveRequest, int) override {
    ++requests;
    return Status::kOk;
  }
  std::int64_t reads = 0;
  int requests = 0;

 private:
  JointGroupInfo info_;
};

TEST(JointStateTap, ForwardsEveryCallAndPublishesEachReadForOtherThreads) {
  CountingGroup group;
  JointStateTap tap(group);
  std::array<JointState, 2> seen{};
  EXPECT_FALSE(tap.latest(seen)) << "nothing read yet";
  std::array<JointState, 2> states{};
  std::int64_t stamp = 0;
  std::thread follower([&] {
    std::array<JointState, 2> mine{};
    while (!tap.latest(mine) || mine[0].position_rad < 1000.0) {
      ASSERT_EQ(mine[0].position_rad, mine[1].position_rad) << "a torn copy";
    }
  });
  for (int i = 0; i < 1000; ++i) ASSERT_EQ(tap.read(states, stamp), Status::kOk);
  follower.join();
  ASSERT_TRUE(tap.latest(seen));
  EXPECT_EQ(seen[1].position_rad, 1000.0);
  EXPECT_EQ(tap.request(DriveRequest::kEnable, JointGroup::kAllJoints), Status::kOk);
  EXPECT_EQ(group.requests, 1);
  std::array<JointState, 3> wrong_size{};
  EXPECT_FALSE(tap.latest(wrong_size));
}

}  // namespace
}  // namespace cambio::hal
