#include "cambio/runtime/realtime_executor.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <csignal>
#include <thread>
#include <vector>

#include "cambio/hal/monotonic_clock.hpp"
#include "recording_loop.hpp"

namespace cambio::runtime {
namespace {

using testing::schedule;

constexpr RealtimeOptions kQuiet{false, /*print_warnings=*/false};

class CountingLoop final : public hal::Loop {
 public:
  explicit CountingLoop(std::string name) : name_(std::move(name)) {}
  const std::string& name() const override { return name_; }
  void configure() override {
    if (fail_configure) throw std::runtime_error("cannot open device");
  }
  hal::Status update(const hal::LoopTick& tick) noexcept override {
    last_cycle = tick.cycle;
    ++updates;
    return hal::Status::kOk;
  }
  void deactivate() noexcept override { deactivated = true; }

  bool fail_configure = false;
  std::atomic<std::uint64_t> updates{0};
  std::atomic<std::uint64_t> last_cycle{0};
  std::atomic<bool> deactivated{false};

 private:
  std::string name_;
};

TEST(RealtimeExecutor, RunsEachLoopAtItsRateForTheDuration) {
  CountingLoop fast("fast");
  CountingLoop slow("slow");
  // catch_up: a late wake-up on a loaded machine runs the missed cycles instead of dropping them.
  auto fast_schedule = schedule(500);
  auto slow_schedule = schedule(50);
  fast_schedule.overrun = slow_schedule.overrun = OverrunPolicy::kCatchUp;
  RealtimeExecutor executor({{&fast, fast_schedule}, {&slow, slow_schedule}}, kQuiet);
  const std::atomic<bool> never{false};
  executor.run(never, 400'000'000);

  // Deadlines are absolute, so the count is exact whatever the scheduling noise: 0.4 s * rate.
  EXPECT_EQ(executor.statistics()[0].cycles, 200u);
  EXPECT_EQ(executor.statistics()[1].cycles, 20u);
  EXPECT_EQ(fast.updates.load(), 200u);
  EXPECT_TRUE(fast.deactivated.load());
  EXPECT_TRUE(slow.deactivated.load());
  EXPECT_GE(executor.statistics()[0].wakeup_latency.count(), 200u);
}

// Overruns on chosen cycles by sleeping through them.
class OverrunningLoop final : public hal::Loop {
 public:
  OverrunningLoop(std::uint64_t cycle_a, std::uint64_t cycle_b, std::int64_t sleep_ns)
      : cycle_a_(cycle_a), cycle_b_(cycle_b), sleep_ns_(sleep_ns) {}
  const std::string& name() const override { return name_; }
  hal::Status update(const hal::LoopTick& tick) noexcept override {
    if (tick.cycle == cycle_a_ || tick.cycle == cycle_b_) {
      std::this_thread::sleep_for(std::chrono::nanoseconds(sleep_ns_));
    }
    return hal::Status::kOk;
  }

 private:
  std::string name_ = "overrunning";
  std::uint64_t cycle_a_;
  std::uint64_t cycle_b_;
  std::int64_t sleep_ns_;
};

TEST(RealtimeExecutor, SkipPolicyAccountsForEveryDeadlineOfTheRunExactlyOnce) {
  // 100 Hz for 100 ms: deadlines 0..9. Cycle 2 sleeps 25 ms (past deadlines 3 and 4, which are
  // skipped); the last cycle, 9, sleeps past the end of the run, which skips nothing.
  OverrunningLoop loop(2, 9, 25'000'000);
  RealtimeExecutor executor({{&loop, schedule(100)}}, kQuiet);
  const std::atomic<bool> never{false};
  executor.run(never, 100'000'000);
  const auto& stats = executor.statistics()[0];
  EXPECT_EQ(stats.cycles + stats.skipped_cycles, 10u);
  EXPECT_GE(stats.skipped_cycles, 2u);
  EXPECT_GE(stats.overruns, 2u);
}

// What /diagnostics reads while the run goes on: from another thread, the cycles grow; at the
// end they and the overruns equal the run's own statistics; the worst wake-up latency and update
// time restart at each read (the overrunning cycle's 25 ms shows once, then no more).
TEST(RealtimeExecutor, LiveStatisticsAreReadableWhileTheLoopsRunAndAgreeWithTheFinalOnes) {
  OverrunningLoop loop(20, 1'000'000, 25'000'000);
  RealtimeExecutor executor({{&loop, schedule(100)}}, kQuiet);
  const std::atomic<bool> never{false};
  std::vector<LiveLoopSample> during;
  std::thread reader([&] {
    for (int k = 0; k < 6; ++k) {
      std::this_thread::sleep_for(std::chrono::milliseconds(60));
      during.push_back(executor.live_statistics().at(0));
    }
  });
  executor.run(never, 400'000'000);
  reader.join();
  ASSERT_EQ(during.size(), 6u);
  EXPECT_EQ(during[0].name, "overrunning");
  EXPECT_EQ(during[0].rate_hz, 100.0);
  EXPECT_GT(during[2].cycles, during[0].cycles) << "counted while running";
  // Cycle 20 (0.2 s in) sleeps 25 ms: one read sees an update of at least that, the last does not.
  const auto longest = std::max_element(
      during.begin(), during.end(),
      [](const auto& a, const auto& b) { return a.max_execution_ns < b.max_execution_ns; });
  EXPECT_GE(longest->max_execution_ns, 25'000'000);
  EXPECT_LT(during.back().max_execution_ns, 25'000'000);
  const LiveLoopSample after = executor.live_statistics().at(0);
  EXPECT_EQ(after.cycles, executor.statistics()[0].cycles);
  EXPECT_EQ(after.overruns, executor.statistics()[0].overruns);
  EXPECT_GE(after.overruns, 1u);
}

std::atomic<bool> g_sigint{false};
extern "C" void on_sigint(int) {
  g_sigint.store(true);
}

TEST(RealtimeExecutor, StopsCleanlyOnSigint) {
  struct sigaction action {};
  struct sigaction previous {};
  action.sa_handler = on_sigint;
  sigemptyset(&action.sa_mask);
  ASSERT_EQ(sigaction(SIGINT, &action, &previous), 0);
  g_sigint.store(false);

  CountingLoop loop("joint");
  RealtimeExecutor executor({{&loop, schedule(1000)}}, kQuiet);
  std::thread interrupter([] {
    std::this_thread::sleep_for(std::chrono::milliseconds(150));
    std::raise(SIGINT);
  });
  const std::int64_t started = executor.clock().now_ns();
  executor.run(g_sigint, /*duration_ns=*/0);  // No duration: only the signal stops it.
  const std::int64_t elapsed = executor.clock().now_ns() - started;
  interrupter.join();
  sigaction(SIGINT, &previous, nullptr);

  EXPECT_TRUE(g_sigint.load());
  EXPECT_TRUE(loop.deactivated.load());
  EXPECT_GT(loop.updates.load(), 50u);
  EXPECT_LT(elapsed, 2'000'000'000) << "the executor did not stop promptly after SIGINT";
}

TEST(RealtimeExecutor, ReportsProgressFromTheCallingThread) {
  CountingLoop loop("joint");
  RealtimeExecutor executor({{&loop, schedule(100)}}, kQuiet);
  std::vector<double> progress;
  const std::atomic<bool> never{false};
  const std::int64_t done_ns =
      executor.run(never, 450'000'000, [&](double done_s) { progress.push_back(done_s); });
  EXPECT_EQ(done_ns, 450'000'000);
  ASSERT_GE(progress.size(), 3u);
  EXPECT_TRUE(std::is_sorted(progress.begin(), progress.end()));
  EXPECT_LE(progress.back(), 0.45);
}

TEST(RealtimeExecutor, RethrowsAConfigureFailureAfterStoppingTheOthers) {
  CountingLoop good("good");
  CountingLoop bad("bad");
  bad.fail_configure = true;
  RealtimeExecutor executor({{&good, schedule(100)}, {&bad, schedule(100)}}, kQuiet);
  const std::atomic<bool> never{false};
  EXPECT_THROW(executor.run(never, 1'000'000'000), std::runtime_error);
  EXPECT_EQ(good.updates.load(), 0u) << "no loop may start when another failed to configure";
  EXPECT_TRUE(good.deactivated.load());
}

TEST(RealtimeExecutor, RefusedPriorityIsAWarningNotAFailure) {
  CountingLoop loop("joint");
  auto rt = schedule(200, 80);
  rt.cpu = 0;
  rt.overrun = OverrunPolicy::kCatchUp;
  RealtimeExecutor executor({{&loop, rt}}, kQuiet);
  const std::atomic<bool> never{false};
  executor.run(never, 50'000'000);
  const auto& warnings = executor.warnings();
  EXPECT_EQ(executor.statistics()[0].cycles, 10u);
  // Whether SCHED_FIFO is granted depends on the machine; either way the loop ran, and a
  // refusal came back as a warning.
  if (!executor.statistics()[0].realtime_priority_granted) {
    ASSERT_FALSE(warnings.empty());
    EXPECT_NE(warnings[0].find("SCHED_FIFO"), std::string::npos);
  }
}

}  // namespace
}  // namespace cambio::runtime
