#include "cambio/control/joint_loop.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <optional>
#include <string>

#include "cambio/control/joint_loop_plan.hpp"
#include "cambio/runtime/allocation_counter.hpp"
#include "cambio/runtime/lockstep_executor.hpp"

namespace cambio::control {
namespace {

// A joint group whose enabled joints go exactly where they are told, with CiA 402 drive states
// it walks one transition per read() (as a drive answers a controlword a cycle later), and
// hooks to fault, freeze or lose a joint. Records every call in `calls`.
class FakeJointGroup final : public hal::JointGroup {
 public:
  explicit FakeJointGroup(std::string name = "head",
                          hal::DriveState initial = hal::DriveState::kOperationEnabled) {
    info_.name = std::move(name);
    info_.backend = "test";
    info_.joints = {"pan", "tilt"};
    hal::JointLimits limits;
    limits.min_position_rad = -1.0;
    limits.max_position_rad = 0.5;
    limits.max_velocity_rad_s = 2.0;
    info_.limits = {limits, limits};
    drive.fill(initial);
  }
  const hal::JointGroupInfo& info() const override { return info_; }
  hal::Status read(std::span<hal::JointState> out, std::int64_t& stamp_ns) override {
    calls.push_back('r');
    if (clock != nullptr) now_ns = clock->now_ns();
    hal::Status status = read_status;
    for (std::size_t j = 0; j < out.size(); ++j) {
      if (pending[j]) {
        const hal::DriveState next = hal::next_drive_state(drive[j], *pending[j]);
        if (next == drive[j]) {
          pending[j].reset();
        } else {
          drive[j] = next;
        }
      }
      if (!frozen[j]) stamp[j] = now_ns;
      out[j] = {};
      out[j].position_rad = position[j];
      out[j].stamp_ns = stamp[j];
      out[j].drive_state = drive[j];
      out[j].error_code = error_code[j];
      out[j].status_bits = extra_bits[j];
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
    calls.push_back('w');
    for (std::size_t j = 0; j < commands.size(); ++j) {
      last[j] = commands[j];
      if (hal::is_enabled(drive[j]) && commands[j].mode == hal::CommandMode::kPosition) {
        position[j] = commands[j].value;
      }
    }
    return hal::Status::kOk;
  }
  hal::Status request(hal::DriveRequest request, int joint) override {
    requests.push_back(request);
    request_joints.push_back(joint);
    if (request == hal::DriveRequest::kHome && joint != kAllJoints &&
        static_cast<std::size_t>(joint) >= homes.size()) {
      return hal::Status::kRejected;
    }
    for (std::size_t j = 0; j < drive.size(); ++j) {
      if (joint == kAllJoints || static_cast<std::size_t>(joint) == j) pending[j] = request;
    }
    if (request == hal::DriveRequest::kFaultReset) error_code.fill(0);
    return hal::Status::kOk;
  }
  hal::Status sync() override {
    calls.push_back('s');
    return hal::Status::kOk;
  }

  void fault(std::size_t joint, std::uint16_t code) {
    drive[joint] = hal::DriveState::kFault;
    error_code[joint] = code;
  }

  std::int64_t now_ns = 0;
  const hal::Clock* clock = nullptr;  ///< When set, read() stamps with its time.
  hal::Status read_status = hal::Status::kOk;
  std::array<double, 2> position{0.0, 0.0};
  std::array<hal::DriveState, 2> drive{};
  std::array<std::optional<hal::DriveRequest>, 2> pending{};
  std::array<std::uint16_t, 2> error_code{};
  std::array<std::uint32_t, 2> extra_bits{};
  std::array<std::int64_t, 2> stamp{};
  std::array<bool, 2> frozen{};
  std::array<hal::JointCommand, 2> last{};
  std::vector<hal::DriveRequest> requests;
  std::vector<int> request_joints;  ///< The joint of each request (kAllJoints: every joint).
  /// The joints that home (a kHome for another joint is refused): the first `homes.size()`.
  std::vector<int> homes = {0, 1};
  std::string calls;

 private:
  hal::JointGroupInfo info_;
};

JointLoopParams test_params() {
  JointLoopParams params;
  params.command_timeout_s = 0.05;
  params.feedback_timeout_s = 0.005;
  params.enable_on_activate = true;
  return params;
}
const JointLoopParams kParams = test_params();

struct Fixture {
  explicit Fixture(hal::DriveState initial = hal::DriveState::kOperationEnabled)
      : group("head", initial) {
    group.calls.reserve(1 << 16);
    group.requests.reserve(64);
    group.request_joints.reserve(64);
    loop.configure();
    loop.activate();
  }
  void command(double pan, double tilt, std::int64_t stamp_ns) {
    JointTargetFrame frame;
    frame.stamp_ns = stamp_ns;
    frame.count = 2;
    frame.commands[0] = {hal::CommandMode::kPosition, pan};
    frame.commands[1] = {hal::CommandMode::kPosition, tilt};
    targets.write(frame);
  }
  hal::Status step(std::uint64_t cycle) {
    const auto t = static_cast<std::int64_t>(cycle) * 1'000'000;  // 1 kHz
    group.now_ns = t;
    return loop.update({cycle, t, t, 1e-3});
  }
  void tick(std::uint64_t cycle) { ASSERT_EQ(step(cycle), hal::Status::kOk); }
  /// Commands (pan, tilt) fresh at every cycle from `first` to `last`, returning the statuses.
  std::vector<hal::Status> drive(double pan, double tilt, std::uint64_t first, std::uint64_t last) {
    std::vector<hal::Status> statuses;
    for (std::uint64_t k = first; k <= last; ++k) {
      command(pan, tilt, static_cast<std::int64_t>(k) * 1'000'000);
      statuses.push_back(step(k));
    }
    return statuses;
  }
  JointStateFrame published() {
    JointStateFrame frame;
    EXPECT_TRUE(states.read(frame));
    return frame;
  }

  FakeJointGroup group;
  hal::SeqlockChannel<JointTargetFrame> targets;
  hal::SeqlockChannel<JointStateFrame> states;
  JointLoop loop{{&group}, targets, states, kParams};
};

TEST(JointLoop, ClampsTargetsToPositionLimits) {
  Fixture f;
  f.command(3.0, -3.0, 0);
  for (std::uint64_t k = 0; k < 1000; ++k) {
    f.command(3.0, -3.0, static_cast<std::int64_t>(k) * 1'000'000);
    f.tick(k);
    ASSERT_LE(f.group.position[0], 0.5);
    ASSERT_GE(f.group.position[1], -1.0);
  }
  EXPECT_DOUBLE_EQ(f.group.position[0], 0.5);
  EXPECT_DOUBLE_EQ(f.group.position[1], -1.0);
}

TEST(JointLoop, TurnsAStepIntoARampAtMaxVelocity) {
  Fixture f;
  // 2 rad/s at 1 kHz: 2 mrad per cycle, so 0.2 rad takes exactly 100 cycles.
  for (std::uint64_t k = 0; k < 150; ++k) {
    f.command(0.2, 0.0, static_cast<std::int64_t>(k) * 1'000'000);
    f.tick(k);
    const double expected = std::min(0.2, 0.002 * static_cast<double>(k + 1));
    ASSERT_NEAR(f.group.position[0], expected, 1e-12) << "cycle " << k;
  }
}

TEST(JointLoop, WatchdogHoldsPositionWhenTargetsGoStale) {
  Fixture f;
  f.command(0.4, 0.0, 0);  // Commanded once at t = 0, never refreshed.
  for (std::uint64_t k = 0; k < 200; ++k) f.tick(k);
  // Fresh for 50 ms (51 cycles, t = 0..50 ms) at 2 mrad per cycle: 0.102 rad, then held.
  EXPECT_NEAR(f.group.position[0], 0.102, 1e-12);
  EXPECT_EQ(f.loop.stale_cycles(), 149u);
}

TEST(JointLoop, CyclesBeforeTheFirstTargetsHoldButAreNoWatchdogEvent) {
  Fixture f;
  for (std::uint64_t k = 0; k < 3; ++k) f.tick(k);  // The controller has not run yet.
  EXPECT_DOUBLE_EQ(f.group.position[0], 0.0);
  EXPECT_EQ(f.loop.awaiting_targets_cycles(), 3u);
  EXPECT_EQ(f.loop.stale_cycles(), 0u);
  f.command(0.4, 0.0, 3'000'000);
  for (std::uint64_t k = 3; k < 100; ++k) f.tick(k);
  // Fresh from 3 ms to 53 ms (51 cycles), then 46 watchdog cycles; start-up stays at 3.
  EXPECT_EQ(f.loop.awaiting_targets_cycles(), 3u);
  EXPECT_EQ(f.loop.stale_cycles(), 46u);
}

TEST(JointLoop, ANonFiniteTargetHoldsTheJointStill) {
  Fixture f;
  f.command(0.1, 0.0, 0);
  f.tick(0);
  f.command(std::nan(""), std::numeric_limits<double>::infinity(), 1'000'000);
  f.tick(1);
  EXPECT_EQ(f.group.last[0].mode, hal::CommandMode::kVelocity);
  EXPECT_EQ(f.group.last[0].value, 0.0);
  EXPECT_EQ(f.group.last[1].mode, hal::CommandMode::kVelocity);
  EXPECT_EQ(f.group.last[1].value, 0.0);
  EXPECT_DOUBLE_EQ(f.group.position[0], 0.002) << "the joint stays where the last ramp left it";
}

TEST(JointLoop, PublishesWhatTheEncodersSay) {
  Fixture f;
  f.group.position = {0.25, -0.5};
  f.command(0.25, -0.5, 0);
  f.tick(0);
  const JointStateFrame frame = f.published();
  EXPECT_EQ(frame.count, 2);
  EXPECT_DOUBLE_EQ(frame.states[0].position_rad, 0.25);
  EXPECT_DOUBLE_EQ(frame.states[1].position_rad, -0.5);
}

TEST(JointLoop, UpdateDoesNotAllocateThroughFaultsStaleReadingsAndResets) {
  Fixture f;
  const auto before = runtime::thread_allocation_count();
  for (std::uint64_t k = 0; k < 10'000; ++k) {
    if (k == 3000) f.group.fault(1, 0x7300);
    if (k == 4000) f.loop.request(hal::DriveRequest::kFaultReset);
    if (k == 4010) f.loop.request(hal::DriveRequest::kEnable);
    f.group.frozen[0] = k >= 6000 && k < 6100;
    f.command(0.1, 0.1, static_cast<std::int64_t>(k) * 1'000'000);
    (void)f.step(k);
  }
  EXPECT_EQ(runtime::thread_allocation_count() - before, 0u);
  EXPECT_GT(f.loop.fault_hold_cycles(), 1000u) << "the faults really happened";
}

TEST(JointLoop, ActivateEnablesTheDrivesAndDeactivateQuickStopsThem) {
  Fixture f(hal::DriveState::kSwitchOnDisabled);
  ASSERT_EQ(f.group.requests.size(), 1u);
  EXPECT_EQ(f.group.requests[0], hal::DriveRequest::kEnable);
  f.loop.deactivate();
  EXPECT_EQ(f.group.requests.back(), hal::DriveRequest::kQuickStop);
}

TEST(JointLoop, EnablingNeverJumpsToAnOldTarget) {
  // The drives are disabled at 0.3 rad; the control loop already asks for 0 rad. While they walk
  // to operation enabled (a transition per cycle) they are sent their measured position; the
  // first target once enabled is exactly that position; then the ramp moves them at max velocity.
  Fixture f(hal::DriveState::kSwitchOnDisabled);
  f.group.position = {0.3, 0.3};
  std::vector<double> sent;
  std::vector<hal::DriveState> states;
  for (std::uint64_t k = 0; k < 10; ++k) {
    f.command(0.0, 0.0, static_cast<std::int64_t>(k) * 1'000'000);
    (void)f.step(k);
    sent.push_back(f.group.last[0].value);
    states.push_back(f.group.drive[0]);
  }
  const auto enabled_at = static_cast<std::size_t>(
      std::find(states.begin(), states.end(), hal::DriveState::kOperationEnabled) - states.begin());
  ASSERT_EQ(enabled_at, 2u) << "disabled -> ready -> switched on -> enabled, one step per read";
  for (std::size_t k = 0; k <= enabled_at; ++k) EXPECT_DOUBLE_EQ(sent[k], 0.3) << "cycle " << k;
  EXPECT_NEAR(sent[enabled_at + 1], 0.298, 1e-12) << "then a ramp, 2 mrad per cycle";
  EXPECT_NEAR(f.group.position[0], 0.3 - 0.002 * 7, 1e-12);
}

TEST(JointLoop, AFaultLatchesHoldsEveryJointUntilResetThenReenablesAtTheMeasuredPosition) {
  Fixture f;
  f.drive(0.2, 0.1, 0, 19);  // Moving: 2 mrad per cycle.
  const std::array<double, 2> at_fault = f.group.position;
  f.group.fault(1, 0x7300);

  // Targets keep changing; nothing moves and the loop reports the fault.
  const auto statuses = f.drive(-0.5, -0.5, 20, 119);
  for (const auto status : statuses) ASSERT_EQ(status, hal::Status::kFault);
  EXPECT_EQ(f.group.position, at_fault) << "no joint moved after the fault";
  JointStateFrame frame = f.published();
  EXPECT_TRUE(frame.fault_latched);
  EXPECT_TRUE(frame.holding);
  EXPECT_NE(frame.states[1].status_bits & hal::kJointFault, 0u);
  EXPECT_EQ(frame.states[1].error_code, 0x7300);
  EXPECT_EQ(frame.states[1].drive_state, hal::DriveState::kFault);

  // The drive comes out of its fault by itself (power cycled): still latched, still holding.
  f.group.drive[1] = hal::DriveState::kSwitchOnDisabled;
  f.group.error_code[1] = 0;
  for (const auto status : f.drive(-0.5, -0.5, 120, 149)) ASSERT_EQ(status, hal::Status::kFault);
  EXPECT_EQ(f.group.position, at_fault);
  EXPECT_NE(f.published().states[1].status_bits & hal::kJointFault, 0u) << "latched";

  // Reset, then enable: the latch clears; joint 1 comes back at its measured position, then
  // every joint ramps towards the new targets.
  f.loop.request(hal::DriveRequest::kFaultReset);
  f.loop.request(hal::DriveRequest::kEnable);
  f.command(-0.5, -0.5, 150'000'000);
  EXPECT_EQ(f.step(150), hal::Status::kOk);
  EXPECT_FALSE(f.published().fault_latched);
  std::vector<double> tilt_sent;
  for (std::uint64_t k = 151; k < 160; ++k) {
    f.command(-0.5, -0.5, static_cast<std::int64_t>(k) * 1'000'000);
    (void)f.step(k);
    tilt_sent.push_back(f.group.last[1].value);
  }
  const auto first_enabled = static_cast<std::size_t>(
      std::find_if(tilt_sent.begin(), tilt_sent.end(), [&](double v) { return v != at_fault[1]; }) -
      tilt_sent.begin());
  ASSERT_LT(first_enabled, tilt_sent.size());
  EXPECT_NEAR(tilt_sent[first_enabled], at_fault[1] - 0.002, 1e-12)
      << "first target after enable is the measured position, then one ramp step";
  EXPECT_LT(f.group.position[0], at_fault[0]) << "motion resumed";
}

// A console's `home JOINT`: the joint's own group is asked, with the joint's index in it, at the
// next cycle; a joint that does not home is refused by its group and the loop counts it.
TEST(JointLoop, AHomeRequestReachesTheJointsGroupWithItsIndexAtTheNextCycle) {
  Fixture f;
  f.group.homes = {0};  // Only the pan homes.
  f.tick(0);
  const std::size_t before = f.group.requests.size();
  EXPECT_TRUE(f.loop.request_home(1));
  EXPECT_TRUE(f.loop.request_home(0));
  EXPECT_FALSE(f.loop.request_home(2)) << "the loop has two joints";
  EXPECT_FALSE(f.loop.request_home(-1));
  EXPECT_EQ(f.group.requests.size(), before) << "nothing before the next cycle";
  f.tick(1);
  ASSERT_EQ(f.group.requests.size(), before + 2);
  EXPECT_EQ(f.group.requests[before], hal::DriveRequest::kHome);
  EXPECT_EQ(f.group.request_joints[before], 0);
  EXPECT_EQ(f.group.request_joints[before + 1], 1);
  EXPECT_EQ(f.loop.homes_refused(), 1u);
  EXPECT_EQ(f.loop.last_refused_home(), 1);
  f.tick(2);
  EXPECT_EQ(f.group.requests.size(), before + 2) << "asked once";
}

/// The requests a loop with `home_after_reboot` forwards after a fault and a reset + enable.
std::vector<hal::DriveRequest> requests_after_reset(bool home_after_reboot) {
  JointLoopParams params = kParams;
  params.home_after_reboot = home_after_reboot;
  FakeJointGroup group;
  hal::SeqlockChannel<JointTargetFrame> targets;
  hal::SeqlockChannel<JointStateFrame> states;
  JointLoop loop({&group}, targets, states, params);
  loop.configure();
  loop.activate();
  for (std::uint64_t k = 0; k < 5; ++k) (void)loop.update({k, 0, 0, 1e-3});
  group.fault(0, 0x8130);
  for (std::uint64_t k = 5; k < 10; ++k) (void)loop.update({k, 0, 0, 1e-3});
  const std::size_t from = group.requests.size();
  loop.request(hal::DriveRequest::kFaultReset);
  loop.request(hal::DriveRequest::kEnable);
  for (std::uint64_t k = 10; k < 20; ++k) (void)loop.update({k, 0, 0, 1e-3});
  return {group.requests.begin() + static_cast<std::ptrdiff_t>(from), group.requests.end()};
}

// A drive that rebooted lost its homing reference: with fault_recovery.home_after_reboot the
// reset's enable is preceded by a home request for every joint (the group homes those that lost
// their reference); without it, no homing is asked and such a joint stays disabled.
TEST(JointLoop, AfterAResetJointsAreAskedToHomeBeforeEnableOnlyWhenTheExperimentAsks) {
  using R = hal::DriveRequest;
  EXPECT_EQ(requests_after_reset(true), (std::vector<R>{R::kFaultReset, R::kHome, R::kEnable}));
  EXPECT_EQ(requests_after_reset(false), (std::vector<R>{R::kFaultReset, R::kEnable}));
}

// experiment.fault_recovery: after holding fault_recovery_delay_s the loop itself asks a reset and
// an enable, at most max_fault_recoveries times; without it (the default) a fault holds for good.
TEST(JointLoop, RecoversByItselfAfterTheDelayAtMostTheAllowedNumberOfTimes) {
  JointLoopParams params = kParams;
  params.fault_recovery_delay_s = 0.05;  // 50 cycles at 1 kHz.
  params.max_fault_recoveries = 1;
  FakeJointGroup group;
  group.requests.reserve(64);
  hal::SeqlockChannel<JointTargetFrame> targets;
  hal::SeqlockChannel<JointStateFrame> states;
  JointLoop loop({&group}, targets, states, params);
  loop.configure();
  loop.activate();
  auto step = [&](std::uint64_t cycle) {
    const auto t = static_cast<std::int64_t>(cycle) * 1'000'000;
    group.now_ns = t;
    JointTargetFrame frame;
    frame.stamp_ns = t;
    frame.count = 2;
    frame.commands[0] = {hal::CommandMode::kPosition, 0.0};
    frame.commands[1] = {hal::CommandMode::kPosition, 0.0};
    targets.write(frame);
    return loop.update({cycle, t, t, 1e-3});
  };
  for (std::uint64_t k = 0; k < 10; ++k) ASSERT_EQ(step(k), hal::Status::kOk);
  group.fault(1, 0x8611);
  const std::size_t requests_before = group.requests.size();
  for (std::uint64_t k = 10; k < 59; ++k) ASSERT_EQ(step(k), hal::Status::kFault) << k;
  EXPECT_EQ(group.requests.size(), requests_before) << "nothing asked before the delay";
  EXPECT_EQ(loop.fault_recoveries(), 0u);
  std::uint64_t k = 59;
  for (; k < 80 && loop.fault_recoveries() == 0; ++k) (void)step(k);
  EXPECT_EQ(k - 1, 60u) << "asked once the latch had lasted 50 ms";
  ASSERT_GE(group.requests.size(), requests_before + 1);
  EXPECT_EQ(group.requests[requests_before], hal::DriveRequest::kFaultReset);
  for (; k < 100; ++k) (void)step(k);
  EXPECT_EQ(group.requests.back(), hal::DriveRequest::kEnable) << "enable once out of the fault";
  EXPECT_FALSE(loop.update({100, 100'000'000, 100'000'000, 1e-3}) == hal::Status::kFault);
  EXPECT_EQ(group.drive[1], hal::DriveState::kOperationEnabled);

  // The allowed recovery is spent: a second fault holds to the end.
  group.fault(0, 0x7300);
  const std::size_t requests_after = group.requests.size();
  for (k = 101; k < 400; ++k) ASSERT_EQ(step(k), hal::Status::kFault);
  EXPECT_EQ(group.requests.size(), requests_after);
  EXPECT_EQ(loop.fault_recoveries(), 1u);
}

TEST(JointLoop, StaleFeedbackHoldsWithoutLatching) {
  Fixture f;
  f.drive(0.2, 0.2, 0, 9);
  const double before = f.group.position[0];
  f.group.frozen[1] = true;  // Joint 1's feedback stops arriving at t = 9 ms.
  const auto statuses = f.drive(0.4, 0.4, 10, 30);
  // Fresh for 5 ms (cycles 10..14), then stale: held.
  for (std::size_t i = 0; i < 5; ++i) EXPECT_EQ(statuses[i], hal::Status::kOk) << i;
  for (std::size_t i = 5; i < statuses.size(); ++i) EXPECT_EQ(statuses[i], hal::Status::kStale);
  EXPECT_NEAR(f.group.position[0], before + 0.002 * 5, 1e-12);
  const JointStateFrame frame = f.published();
  EXPECT_NE(frame.states[1].status_bits & hal::kJointStale, 0u);
  EXPECT_TRUE(frame.holding);
  EXPECT_FALSE(frame.fault_latched);
  f.group.frozen[1] = false;  // Fresh again: motion resumes without a reset.
  f.drive(0.4, 0.4, 31, 31);
  EXPECT_NEAR(f.group.position[0], before + 0.002 * 6, 1e-12);
  EXPECT_EQ(f.loop.feedback_stale_cycles(), 16u);
}

TEST(JointLoop, LostCommunicationLatchesLikeAFault) {
  Fixture f;
  f.drive(0.2, 0.2, 0, 9);
  f.group.extra_bits[0] = hal::kJointCommLost;
  f.drive(0.4, 0.4, 10, 10);
  f.group.extra_bits[0] = 0;  // The heartbeat comes back: the loop still holds.
  const double held = f.group.position[0];
  for (const auto status : f.drive(0.4, 0.4, 11, 40)) EXPECT_EQ(status, hal::Status::kFault);
  EXPECT_EQ(f.group.position[0], held);
  EXPECT_NE(f.published().states[0].status_bits & hal::kJointCommLost, 0u);
  f.loop.request(hal::DriveRequest::kFaultReset);
  f.drive(0.4, 0.4, 41, 42);
  EXPECT_GT(f.group.position[0], held);
}

TEST(JointLoop, ReportsTheMostSevereStatusOfItsGroupsNotTheLastOne) {
  FakeJointGroup faulty("faulty");
  FakeJointGroup healthy("healthy");
  faulty.read_status = hal::Status::kRejected;
  hal::SeqlockChannel<JointTargetFrame> targets;
  hal::SeqlockChannel<JointStateFrame> states;
  JointLoop loop({&faulty, &healthy}, targets, states, kParams);
  loop.configure();
  loop.activate();
  EXPECT_EQ(loop.update({0, 0, 0, 1e-3}), hal::Status::kRejected);
  faulty.read_status = hal::Status::kOk;
  healthy.read_status = hal::Status::kStale;
  EXPECT_EQ(loop.update({1, 1'000'000, 1'000'000, 1e-3}), hal::Status::kStale);
}

TEST(JointLoop, EachCycleReadsThenWritesThenSyncs) {
  Fixture f;
  f.group.calls.clear();
  f.drive(0.1, 0.1, 0, 2);
  EXPECT_EQ(f.group.calls, "rwsrwsrws");
}

}  // namespace
}  // namespace cambio::control

namespace cambio::control {
namespace {

hal::JointGroupInfo group_at(const std::string& name, double rate_hz) {
  hal::JointGroupInfo info;
  info.name = name;
  info.rate_hz = rate_hz;
  return info;
}

TEST(JointLoopPlan, GroupsAtTheRigRateShareJointOthersALoopPerRate) {
  const auto plans = plan_joint_loops(
      {group_at("head", 0.0), group_at("left_arm", 250.0), group_at("right_arm", 250.0),
       group_at("gripper", 400.0), group_at("wrist", 100.0)},
      400.0);
  ASSERT_EQ(plans.size(), 3u);
  EXPECT_EQ(plans[0].name, "joint");
  EXPECT_EQ(plans[0].rate_hz, 400.0);
  EXPECT_EQ(plans[0].groups, (std::vector<std::size_t>{0, 3}));
  EXPECT_EQ(plans[1].name, "joint.left_arm+right_arm");
  EXPECT_EQ(plans[1].rate_hz, 250.0);
  EXPECT_EQ(plans[1].groups, (std::vector<std::size_t>{1, 2}));
  EXPECT_EQ(plans[2].name, "joint.wrist");
  EXPECT_EQ(plans[2].groups, (std::vector<std::size_t>{4}));
}

TEST(JointLoopPlan, NoGroupRateKeepsTheOneJointLoop) {
  const auto plans = plan_joint_loops({group_at("head", 0.0), group_at("arm", 0.0)}, 1000.0);
  ASSERT_EQ(plans.size(), 1u);
  EXPECT_EQ(plans[0].name, "joint");
  EXPECT_EQ(plans[0].groups, (std::vector<std::size_t>{0, 1}));
  // Every group at its own rate: no empty "joint" loop.
  const auto own = plan_joint_loops({group_at("head", 500.0)}, 1000.0);
  ASSERT_EQ(own.size(), 1u);
  EXPECT_EQ(own[0].name, "joint.head");
  EXPECT_THROW(plan_joint_loops({group_at("head", -1.0)}, 1000.0), std::invalid_argument);
}

// Stands for the control loop: fresh rig-wide targets every cycle (head pan, tilt, arm pan, tilt).
class TargetLoop final : public hal::Loop {
 public:
  TargetLoop(hal::SeqlockChannel<JointTargetFrame>& targets, const hal::Clock& clock)
      : targets_(targets), clock_(clock) {}
  const std::string& name() const override { return name_; }
  hal::Status update(const hal::LoopTick&) noexcept override {
    JointTargetFrame frame;
    frame.stamp_ns = clock_.now_ns();
    frame.count = 4;
    for (std::size_t j = 0; j < 4; ++j) frame.commands[j] = {hal::CommandMode::kPosition, value[j]};
    targets_.write(frame);
    return hal::Status::kOk;
  }
  std::array<double, 4> value{0.1, 0.2, -0.3, -0.4};

 private:
  std::string name_ = "control";
  hal::SeqlockChannel<JointTargetFrame>& targets_;
  const hal::Clock& clock_;
};

// The main job's wiring of two groups at two rates (apps/run_assembly/main_job.cpp): one loop per
// rate, each taking its joints from the rig-wide target frame, sharing a RigHold.
struct TwoRateRig {
  TwoRateRig() {
    head.clock = arm.clock = &executor.clock();
    head.calls.reserve(1 << 14);
    arm.calls.reserve(1 << 14);
    JointLoopParams head_params = kParams;
    head_params.name = "joint";
    head_params.target_indices = {0, 1};
    head_params.target_count = 4;
    head_params.rig_hold = &hold;
    JointLoopParams arm_params = kParams;
    arm_params.name = "joint.arm";
    arm_params.target_indices = {2, 3};
    arm_params.target_count = 4;
    arm_params.rig_hold = &hold;
    head_loop = std::make_unique<JointLoop>(std::vector<hal::JointGroup*>{&head}, targets,
                                            head_states, head_params);
    arm_loop = std::make_unique<JointLoop>(std::vector<hal::JointGroup*>{&arm}, targets, arm_states,
                                           arm_params);
    executor.add_loop({head_loop.get(), {400.0}});
    executor.add_loop({arm_loop.get(), {250.0}});
    executor.add_loop({&control, {200.0}});
    executor.configure();
  }
  static long count(const std::string& calls, char c) {
    return static_cast<long>(std::count(calls.begin(), calls.end(), c));
  }

  runtime::LockstepExecutor executor;
  FakeJointGroup head{"head"};
  FakeJointGroup arm{"arm"};
  RigHold hold;
  hal::SeqlockChannel<JointTargetFrame> targets;
  hal::SeqlockChannel<JointStateFrame> head_states;
  hal::SeqlockChannel<JointStateFrame> arm_states;
  std::unique_ptr<JointLoop> head_loop;
  std::unique_ptr<JointLoop> arm_loop;
  TargetLoop control{targets, executor.clock()};
};

TEST(JointLoopsAtTwoRates, EachGroupIsUpdatedAtItsOwnRateWithItsOwnTargets) {
  TwoRateRig rig;
  rig.executor.run_until_ns(500'000'000);  // 0.5 s: deadlines at k / rate for k = 0, 1, ...
  // Activation reads once; then one read, write and sync per cycle of each group's own loop.
  EXPECT_EQ(TwoRateRig::count(rig.head.calls, 'w'), 200);
  EXPECT_EQ(TwoRateRig::count(rig.head.calls, 's'), 200);
  EXPECT_EQ(TwoRateRig::count(rig.arm.calls, 'w'), 125);
  EXPECT_EQ(TwoRateRig::count(rig.arm.calls, 's'), 125);
  // Each group reached its own slice of the rig-wide targets (ramped at 2 rad/s: 0.2 s at most).
  EXPECT_DOUBLE_EQ(rig.head.position[0], 0.1);
  EXPECT_DOUBLE_EQ(rig.head.position[1], 0.2);
  EXPECT_DOUBLE_EQ(rig.arm.position[0], -0.3);
  EXPECT_DOUBLE_EQ(rig.arm.position[1], -0.4);
  // The ramp runs at each loop's own period: one arm cycle moves at most 2 rad/s x 4 ms.
  JointStateFrame arm_frame;
  ASSERT_TRUE(rig.arm_states.read(arm_frame));
  EXPECT_EQ(arm_frame.count, 2);
  EXPECT_FALSE(arm_frame.holding);
  rig.executor.deactivate();
}

TEST(JointLoopsAtTwoRates, AFaultInOneLoopHoldsTheOther) {
  TwoRateRig rig;
  rig.executor.run_until_ns(300'000'000);
  rig.arm.fault(0, 0x8611);
  rig.control.value = {-0.5, -0.5, -0.3, -0.4};  // The head is told to move.
  rig.executor.run_until_ns(400'000'000);
  JointStateFrame head_frame;
  ASSERT_TRUE(rig.head_states.read(head_frame));
  EXPECT_TRUE(head_frame.holding);
  EXPECT_FALSE(head_frame.fault_latched);  // The fault is the arm's.
  // Held from the arm loop's first faulted cycle (within 4 ms): the head moved at most one
  // 400 Hz step (2 rad/s x 2.5 ms) towards -0.5 before the hold, then stayed.
  EXPECT_GE(rig.head.position[0], 0.1 - 2 * 0.0025 - 1e-12);
  EXPECT_GT(rig.head_loop->fault_hold_cycles(), 30u);
  // The arm's reset clears its latch; the head then follows its targets again.
  rig.arm_loop->request(hal::DriveRequest::kFaultReset);
  rig.arm_loop->request(hal::DriveRequest::kEnable);
  rig.executor.run_until_ns(1'200'000'000);
  ASSERT_TRUE(rig.head_states.read(head_frame));
  EXPECT_FALSE(head_frame.holding);
  EXPECT_DOUBLE_EQ(rig.head.position[0], -0.5);
  rig.executor.deactivate();
}

}  // namespace
}  // namespace cambio::control
