#pragma once

#include <atomic>
#include <cstdint>
#include <string>
#include <vector>

#include "cambio/hal/clock.hpp"
#include "cambio/runtime/loop_statistics.hpp"
#include "cambio/runtime/scheduled_loop.hpp"

namespace cambio::runtime {

struct RealtimeOptions {
  bool lock_memory = false;  ///< mlockall(MCL_CURRENT | MCL_FUTURE) before the loops start.
};

/// One thread per loop, each sleeping with clock_nanosleep(CLOCK_MONOTONIC, TIMER_ABSTIME) on
/// absolute deadlines, with the loop's SCHED_FIFO priority and CPU affinity where the system
/// grants them (a warning, not a failure, where it refuses). Stops when `stop` becomes true
/// (e.g. set from a SIGINT handler) or when the duration elapses.
class RealtimeExecutor {
 public:
  RealtimeExecutor(hal::Clock& clock, std::vector<ScheduledLoop> loops, RealtimeOptions options);

  /// Runs configure() and activate() of each loop on its own thread, then the cycles, until
  /// `stop` is set or `duration_ns` (<= 0: no limit) has passed; then deactivate(). Returns the
  /// warnings (refused priority, affinity, mlockall), also printed to stderr if `print_warnings`.
  /// Rethrows the first exception a loop's configure() threw, after stopping the others.
  std::vector<std::string> run(const std::atomic<bool>& stop, std::int64_t duration_ns,
                               bool print_warnings = true);

  const std::vector<LoopStatistics>& statistics() const { return stats_; }

 private:
  hal::Clock& clock_;
  std::vector<ScheduledLoop> loops_;
  RealtimeOptions options_;
  std::vector<LoopStatistics> stats_;
};

}  // namespace cambio::runtime
