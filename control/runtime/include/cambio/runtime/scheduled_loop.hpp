#pragma once

#include <cstdint>
#include <string>

#include "cambio/hal/loop.hpp"

namespace cambio::runtime {

/// What an executor does when a cycle ends after the next deadline.
enum class OverrunPolicy : std::uint8_t {
  kSkip,     ///< Drop the missed deadlines; the next cycle is the next one in the future.
  kCatchUp,  ///< Run the missed cycles back to back.
};

/// How to run one loop. The runtime's own type: the application maps its configuration onto it,
/// so the runtime needs no config library.
struct LoopSchedule {
  double rate_hz = 0.0;
  int priority = 0;  ///< SCHED_FIFO priority 1..99 under the realtime executor; 0 = normal.
  int cpu = -1;      ///< CPU to pin the loop's thread to; -1 = any.
  OverrunPolicy overrun = OverrunPolicy::kSkip;
};

/// A loop and how to run it. The executor does not own the loop.
struct ScheduledLoop {
  hal::Loop* loop = nullptr;
  LoopSchedule schedule;
};

/// The k-th deadline of a loop started at start_ns: start + round(k * 1e9 / rate_hz).
/// Computed from k, not accumulated, so rates are exact over any run length (no drift).
std::int64_t deadline_ns(std::int64_t start_ns, std::uint64_t k, double rate_hz);

}  // namespace cambio::runtime
