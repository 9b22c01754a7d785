#pragma once

#include <atomic>

#include "cambio/hal/clock.hpp"

namespace cambio::hal {

/// Simulated time that moves only when told to. The lockstep executor owns it: it sets the time
/// to the next loop deadline before running that loop, so sleep_until_ns() never waits.
class ManualClock final : public Clock {
 public:
  explicit ManualClock(std::int64_t start_ns = 0) : now_ns_(start_ns) {}
  std::int64_t now_ns() const override { return now_ns_.load(std::memory_order_acquire); }
  /// Jumps forward to the deadline (time never goes backwards).
  void sleep_until_ns(std::int64_t deadline_ns) override { advance_to_ns(deadline_ns); }
  void advance_to_ns(std::int64_t t_ns) {
    if (t_ns > now_ns_.load(std::memory_order_relaxed)) {
      now_ns_.store(t_ns, std::memory_order_release);
    }
  }

 private:
  std::atomic<std::int64_t> now_ns_;
};

}  // namespace cambio::hal
