#pragma once

#include <cstdint>

#include "cambio/config/rig_config.hpp"
#include "cambio/hal/loop.hpp"

namespace cambio::runtime {

/// A loop and how to run it (rate, priority, CPU, overrun policy). The executor does not own
/// the loop.
struct ScheduledLoop {
  hal::Loop* loop = nullptr;
  config::LoopConfig schedule;
};

/// The k-th deadline of a loop started at start_ns: start + round(k * 1e9 / rate_hz).
/// Computed from k, not accumulated, so rates are exact over any run length (no drift).
std::int64_t deadline_ns(std::int64_t start_ns, std::uint64_t k, double rate_hz);

}  // namespace cambio::runtime
