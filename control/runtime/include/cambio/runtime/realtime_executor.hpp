#pragma once

#include <atomic>
#include <cstdint>
#include <string>
#include <vector>

#include "cambio/hal/monotonic_clock.hpp"
#include "cambio/runtime/executor.hpp"
#include "cambio/runtime/loop_statistics.hpp"
#include "cambio/runtime/scheduled_loop.hpp"

namespace cambio::runtime {

struct RealtimeOptions {
  bool lock_memory = false;    ///< mlockall(MCL_CURRENT | MCL_FUTURE) before the loops start.
  bool print_warnings = true;  ///< Also print warnings() to stderr as they happen.
};

/// One thread per loop, each sleeping with clock_nanosleep(CLOCK_MONOTONIC, TIMER_ABSTIME) on
/// absolute deadlines of its own MonotonicClock, with the loop's SCHED_FIFO priority and CPU
/// affinity where the system grants them (a warning, not a failure, where it refuses). Stops
/// when `stop` becomes true (e.g. set from a SIGINT handler) or when the duration elapses.
class RealtimeExecutor final : public Executor {
 public:
  explicit RealtimeExecutor(std::vector<ScheduledLoop> loops = {}, RealtimeOptions options = {});

  hal::Clock& clock() override { return clock_; }
  void add_loop(ScheduledLoop loop) override;
  /// Runs configure() and activate() of each loop on its own thread, then the cycles, until
  /// `stop` is set or `duration_ns` (<= 0: no limit) has passed; then deactivate(). The calling
  /// thread reports progress meanwhile. Rethrows the first exception a loop's configure() or
  /// activate() threw, after stopping the others.
  std::int64_t run(const std::atomic<bool>& stop, std::int64_t duration_ns,
                   const Progress& progress = {}) override;
  const std::vector<LoopStatistics>& statistics() const override { return stats_; }

  /// Refused priority, affinity or mlockall of the last run.
  const std::vector<std::string>& warnings() const { return warnings_; }

 private:
  /// What one run's threads share (realtime_executor.cpp).
  struct RunState;

  /// Records a refusal (printed too, with print_warnings); safe from the loops' threads.
  void warn(RunState& state, std::string text);
  /// The body of loop `index`'s thread.
  void run_loop(std::size_t index, RunState& state);
  /// The loop's CPU affinity and SCHED_FIFO priority, where the system grants them.
  void pin_to_cpu(const ScheduledLoop& scheduled, LoopStatistics& stats, RunState& state);
  void raise_priority(const ScheduledLoop& scheduled, LoopStatistics& stats, RunState& state);
  /// False (the run aborted, the exception kept) when either throws.
  bool configure_and_activate(std::size_t index, RunState& state);
  /// Waits for every loop to be configured; returns the start the loops share.
  std::int64_t wait_for_common_start(std::size_t index, RunState& state);
  void run_cycles(const ScheduledLoop& scheduled, LoopStatistics& stats, LiveLoopCounters& live,
                  std::int64_t start, RunState& state);
  void report_progress_until_finished(RunState& state, const Progress& progress);

  hal::MonotonicClock clock_;
  std::vector<ScheduledLoop> loops_;
  RealtimeOptions options_;
  std::vector<LoopStatistics> stats_;
  std::vector<std::string> warnings_;
};

}  // namespace cambio::runtime
