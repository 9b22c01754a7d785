#pragma once

// What another thread may read of a loop while the run goes on (the ROS 2 bridge's
// /diagnostics): counters the loop's own thread updates with relaxed atomics after each update,
// no lock, no allocation. LoopStatistics holds the whole story, but only once the run ended.

#include <algorithm>
#include <atomic>
#include <cstdint>
#include <string>

namespace cambio::runtime {

/// One loop, as read while it runs.
struct LiveLoopSample {
  std::string name;
  double rate_hz = 0.0;  ///< Its schedule's.
  std::uint64_t cycles = 0;
  std::uint64_t overruns = 0;  ///< Updates that ended after the next deadline.
  /// The largest wake-up latency (now - deadline at the start of an update) and update duration
  /// since the previous read_and_reset(), ns; 0 when no cycle ran since.
  std::int64_t max_wakeup_latency_ns = 0;
  std::int64_t max_execution_ns = 0;
};

class LiveLoopCounters {
 public:
  /// The loop's thread, after each update.
  void record(std::int64_t wakeup_latency_ns, std::int64_t execution_ns, bool overrun) noexcept {
    cycles_.fetch_add(1, std::memory_order_relaxed);
    if (overrun) overruns_.fetch_add(1, std::memory_order_relaxed);
    raise(max_wakeup_latency_ns_, wakeup_latency_ns);
    raise(max_execution_ns_, execution_ns);
  }
  /// Any thread (one reader: the maxima restart at each read).
  void read_and_reset(LiveLoopSample& out) noexcept {
    out.cycles = cycles_.load(std::memory_order_relaxed);
    out.overruns = overruns_.load(std::memory_order_relaxed);
    out.max_wakeup_latency_ns = max_wakeup_latency_ns_.exchange(0, std::memory_order_relaxed);
    out.max_execution_ns = max_execution_ns_.exchange(0, std::memory_order_relaxed);
  }

 private:
  static void raise(std::atomic<std::int64_t>& maximum, std::int64_t value) noexcept {
    std::int64_t seen = maximum.load(std::memory_order_relaxed);
    while (value > seen && !maximum.compare_exchange_weak(seen, value, std::memory_order_relaxed)) {
    }
  }

  std::atomic<std::uint64_t> cycles_{0};
  std::atomic<std::uint64_t> overruns_{0};
  std::atomic<std::int64_t> max_wakeup_latency_ns_{0};
  std::atomic<std::int64_t> max_execution_ns_{0};
};

}  // namespace cambio::runtime
