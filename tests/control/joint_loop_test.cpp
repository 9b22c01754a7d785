#include "cambio/control/joint_loop.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "cambio/runtime/allocation_counter.hpp"

namespace cambio::control {
namespace {

// A joint group whose joints go exactly where they are told, recording what they were told.
class PerfectJointGroup final : public hal::JointGroup {
 public:
  PerfectJointGroup() {
    info_.name = "head";
    info_.backend = "test";
    info_.joints = {"pan", "tilt"};
    hal::JointLimits limits;
    limits.min_position_rad = -1.0;
    limits.max_position_rad = 0.5;
    limits.max_velocity_rad_s = 2.0;
    info_.limits = {limits, limits};
  }
  const hal::JointGroupInfo& info() const override { return info_; }
  hal::Status read(std::span<hal::JointState> out, std::int64_t& stamp_ns) override {
    for (std::size_t j = 0; j < out.size(); ++j) out[j].position_rad = position[j];
    stamp_ns = 0;
    return hal::Status::kOk;
  }
  hal::Status write(std::span<const hal::JointCommand> commands) override {
    for (std::size_t j = 0; j < commands.size(); ++j) {
      if (commands[j].mode == hal::CommandMode::kPosition) position[j] = commands[j].value;
      last[j] = commands[j];
    }
    return hal::Status::kOk;
  }
  std::array<double, 2> position{0.0, 0.0};
  std::array<hal::JointCommand, 2> last{};

 private:
  hal::JointGroupInfo info_;
};

struct Fixture {
  PerfectJointGroup group;
  hal::SeqlockChannel<JointTargetFrame> targets;
  hal::SeqlockChannel<JointStateFrame> states;
  JointLoop loop{{&group}, targets, states, /*command_timeout_s=*/0.05};

  Fixture() {
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
  void tick(std::uint64_t cycle) {
    const auto t = static_cast<std::int64_t>(cycle) * 1'000'000;  // 1 kHz
    ASSERT_EQ(loop.update({cycle, t, t, 1e-3}), hal::Status::kOk);
  }
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
  JointStateFrame frame;
  f.states.read(frame);
  EXPECT_EQ(frame.count, 2);
  EXPECT_DOUBLE_EQ(frame.states[0].position_rad, 0.25);
  EXPECT_DOUBLE_EQ(frame.states[1].position_rad, -0.5);
}

TEST(JointLoop, UpdateDoesNotAllocate) {
  Fixture f;
  const auto before = runtime::thread_allocation_count();
  for (std::uint64_t k = 0; k < 10'000; ++k) {
    f.command(0.1, 0.1, static_cast<std::int64_t>(k) * 1'000'000);
    f.tick(k);
  }
  EXPECT_EQ(runtime::thread_allocation_count() - before, 0u);
}

}  // namespace
}  // namespace cambio::control
