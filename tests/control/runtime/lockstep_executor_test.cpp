#include "cambio/runtime/lockstep_executor.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include "recording_loop.hpp"

namespace cambio::runtime {
namespace {

using testing::RecordingLoop;
using testing::schedule;
using testing::TraceEntry;

std::vector<TraceEntry> run_two_loops(std::int64_t duration_ns) {
  hal::ManualClock clock;
  std::vector<TraceEntry> trace;
  RecordingLoop joint("joint", clock, trace);
  RecordingLoop control("control", clock, trace);
  // control is listed first but joint has the higher priority: joint must run first on ties.
  LockstepExecutor executor(
      clock, {{&control, schedule("control", 200, 70)}, {&joint, schedule("joint", 1000, 80)}});
  executor.configure();
  executor.run_until_ns(duration_ns);
  executor.deactivate();
  return trace;
}

TEST(LockstepExecutor, RunsEachLoopAtExactlyItsRateOnSimulatedTime) {
  hal::ManualClock clock;
  std::vector<TraceEntry> trace;
  RecordingLoop joint("joint", clock, trace);
  RecordingLoop camera("camera", clock, trace);
  LockstepExecutor executor(clock,
                            {{&joint, schedule("joint", 1000)}, {&camera, schedule("camera", 30)}});
  executor.configure();
  executor.run_until_ns(10'000'000'000);  // 10 s of simulated time.

  const auto& stats = executor.statistics();
  EXPECT_EQ(stats[0].cycles, 10'000u);
  EXPECT_EQ(stats[1].cycles, 300u);
  EXPECT_EQ(clock.now_ns(), 10'000'000'000);
  // 30 Hz has no whole-nanosecond period: deadlines are rounded from k, never accumulated.
  for (const auto& entry : trace) {
    const double rate = entry.loop == "joint" ? 1000.0 : 30.0;
    const auto expected = static_cast<std::int64_t>(std::llround(entry.cycle * 1e9 / rate));
    ASSERT_EQ(entry.deadline_ns, expected) << entry.loop << " cycle " << entry.cycle;
    ASSERT_EQ(entry.clock_ns, expected) << "the clock reads the deadline while the loop runs";
  }
  EXPECT_EQ(joint.configure_calls, 1);
  EXPECT_EQ(joint.activate_calls, 1);
}

TEST(LockstepExecutor, OrdersByDeadlineThenPriority) {
  const auto trace = run_two_loops(10'000'000);
  ASSERT_GE(trace.size(), 3u);
  EXPECT_EQ(trace[0], (TraceEntry{"joint", 0, 0, 0}));
  EXPECT_EQ(trace[1], (TraceEntry{"control", 0, 0, 0}));
  EXPECT_EQ(trace[2], (TraceEntry{"joint", 1'000'000, 1, 1'000'000}));
  for (std::size_t i = 1; i < trace.size(); ++i) {
    ASSERT_LE(trace[i - 1].clock_ns, trace[i].clock_ns) << "time went backwards at " << i;
  }
  // At 5 ms both are due again; joint still goes first.
  const auto at_5ms = std::find_if(trace.begin(), trace.end(),
                                   [](const TraceEntry& e) { return e.clock_ns == 5'000'000; });
  ASSERT_NE(at_5ms, trace.end());
  EXPECT_EQ(at_5ms->loop, "joint");
  EXPECT_EQ((at_5ms + 1)->loop, "control");
}

TEST(LockstepExecutor, IsDeterministic) {
  EXPECT_EQ(run_two_loops(2'000'000'000), run_two_loops(2'000'000'000));
}

TEST(LockstepExecutor, ResumesWhereItStopped) {
  hal::ManualClock clock;
  std::vector<TraceEntry> split_trace;
  RecordingLoop loop("joint", clock, split_trace);
  LockstepExecutor executor(clock, {{&loop, schedule("joint", 1000)}});
  executor.configure();
  executor.run_until_ns(3'500'000);
  executor.run_until_ns(7'000'000);
  ASSERT_EQ(split_trace.size(), 7u);
  for (std::uint64_t k = 0; k < split_trace.size(); ++k) {
    EXPECT_EQ(split_trace[k].cycle, k);
    EXPECT_EQ(split_trace[k].clock_ns, static_cast<std::int64_t>(k) * 1'000'000);
  }
}

TEST(LockstepExecutor, RefusesAZeroRate) {
  hal::ManualClock clock;
  std::vector<TraceEntry> trace;
  RecordingLoop loop("joint", clock, trace);
  EXPECT_THROW(LockstepExecutor(clock, {{&loop, schedule("joint", 0)}}), std::invalid_argument);
}

TEST(DeadlineNs, IsExactForLongRuns) {
  // 100 days at 1 kHz: k * period must not drift by even a nanosecond.
  const std::uint64_t k = 100ull * 24 * 3600 * 1000;
  EXPECT_EQ(deadline_ns(5, k, 1000.0), 5 + static_cast<std::int64_t>(k) * 1'000'000);
  EXPECT_EQ(deadline_ns(0, 3, 3.0), 1'000'000'000);
  EXPECT_EQ(deadline_ns(0, 1, 3.0), 333'333'333);
}

}  // namespace
}  // namespace cambio::runtime
