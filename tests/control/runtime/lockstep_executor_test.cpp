#include "cambio/runtime/lockstep_executor.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <random>
#include <stdexcept>

#include "recording_loop.hpp"

namespace cambio::runtime {
namespace {

using testing::RecordingLoop;
using testing::schedule;
using testing::TraceEntry;

std::vector<TraceEntry> run_two_loops(std::int64_t duration_ns, void (*work)() = nullptr) {
  LockstepExecutor executor;
  std::vector<TraceEntry> trace;
  trace.reserve(static_cast<std::size_t>(duration_ns / 1'000'000 * 2));
  RecordingLoop joint("joint", executor.clock(), trace);
  RecordingLoop control("control", executor.clock(), trace);
  joint.work = work;
  // control is listed first but joint has the higher priority: joint must run first on ties.
  executor.add_loop({&control, schedule(200, 70)});
  executor.add_loop({&joint, schedule(1000, 80)});
  executor.configure();
  executor.run_until_ns(duration_ns);
  executor.deactivate();
  return trace;
}

// Burns a random amount of wall time (0-50 µs), different on every call and every run.
void burn_random_wall_time() {
  static std::random_device entropy;
  const auto until =
      std::chrono::steady_clock::now() + std::chrono::nanoseconds(entropy() % 50'000);
  while (std::chrono::steady_clock::now() < until) {
  }
}

TEST(LockstepExecutor, RunsEachLoopAtExactlyItsRateOnSimulatedTime) {
  LockstepExecutor executor;
  hal::ManualClock& clock = executor.clock();
  std::vector<TraceEntry> trace;
  trace.reserve(10'300);
  RecordingLoop joint("joint", clock, trace);
  RecordingLoop camera("camera", clock, trace);
  executor.add_loop({&joint, schedule(1000)});
  executor.add_loop({&camera, schedule(30)});
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

TEST(LockstepExecutor, IsDeterministicWhateverTheWallClockDoes) {
  // Each update takes a random wall time: if the executor let wall time leak into the order of
  // the loops, their ticks or the clock they read, two runs would differ.
  const auto first = run_two_loops(200'000'000, burn_random_wall_time);
  const auto second = run_two_loops(200'000'000, burn_random_wall_time);
  ASSERT_EQ(first.size(), 240u);
  EXPECT_EQ(first, second);
}

TEST(LockstepExecutor, ResumesWhereItStopped) {
  LockstepExecutor executor;
  std::vector<TraceEntry> split_trace;
  split_trace.reserve(16);
  RecordingLoop loop("joint", executor.clock(), split_trace);
  executor.add_loop({&loop, schedule(1000)});
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
  EXPECT_THROW(LockstepExecutor({{&loop, schedule(0)}}), std::invalid_argument);
}

TEST(LockstepExecutor, RunReportsProgressAndCollectsLoopFaults) {
  LockstepExecutor executor;
  std::vector<TraceEntry> trace;
  trace.reserve(5);  // Fills after 5 cycles: every later update reports a fault.
  RecordingLoop loop("joint", executor.clock(), trace);
  executor.add_loop({&loop, schedule(100)});
  std::vector<double> progress;
  const std::atomic<bool> never{false};
  EXPECT_EQ(executor.run(never, 250'000'000, [&](double done_s) { progress.push_back(done_s); }),
            250'000'000);
  EXPECT_EQ(progress, (std::vector<double>{0.1, 0.2, 0.25}));
  const LoopStatistics& stats = executor.statistics()[0];
  EXPECT_EQ(stats.cycles, 25u);
  EXPECT_EQ(stats.failed_updates, 20u);
  EXPECT_EQ(stats.faults, 20u);
  EXPECT_EQ(stats.fault_message, "trace full");
  EXPECT_EQ(loop.deactivate_calls, 1);
}

// A loop whose work calls something that throws (a library's control law).
class ThrowingLoop final : public hal::Loop {
 public:
  const std::string& name() const override { return name_; }
  hal::Status update(const hal::LoopTick& tick) noexcept override {
    return guarded([&] {
      if (tick.cycle % 2 == 1) throw std::runtime_error("singular interaction matrix");
      return hal::Status::kOk;
    });
  }

 private:
  std::string name_ = "servo";
};

TEST(LockstepExecutor, AnExceptionInsideAGuardedUpdateIsAFaultOfThatLoopNotATermination) {
  ThrowingLoop loop;
  LockstepExecutor executor({{&loop, schedule(100)}});
  const std::atomic<bool> never{false};
  executor.run(never, 100'000'000, {});
  const LoopStatistics& stats = executor.statistics()[0];
  EXPECT_EQ(stats.cycles, 10u);
  EXPECT_EQ(stats.failed_updates, 5u);
  EXPECT_EQ(stats.faults, 5u);
  EXPECT_EQ(stats.fault_message, "singular interaction matrix");
  EXPECT_NE(format_statistics_table(&stats, 1).find("singular interaction matrix"),
            std::string::npos);
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
