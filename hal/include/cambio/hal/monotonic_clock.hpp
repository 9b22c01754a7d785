#pragma once

#include <cerrno>
#include <ctime>

#include "cambio/hal/clock.hpp"

namespace cambio::hal {

/// CLOCK_MONOTONIC, sleeping with clock_nanosleep on absolute deadlines (no drift from
/// relative sleeps).
class MonotonicClock final : public Clock {
 public:
  std::int64_t now_ns() const override {
    timespec ts{};
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return static_cast<std::int64_t>(ts.tv_sec) * 1'000'000'000 + ts.tv_nsec;
  }
  void sleep_until_ns(std::int64_t deadline_ns) override {
    timespec ts{};
    ts.tv_sec = static_cast<time_t>(deadline_ns / 1'000'000'000);
    ts.tv_nsec = static_cast<long>(deadline_ns % 1'000'000'000);
    // Restart after a signal: the deadline is absolute, so retrying does not lengthen the sleep.
    while (clock_nanosleep(CLOCK_MONOTONIC, TIMER_ABSTIME, &ts, nullptr) == EINTR) {
    }
  }
};

}  // namespace cambio::hal
