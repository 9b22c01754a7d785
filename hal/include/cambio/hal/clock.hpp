#pragma once

#include <cstdint>

namespace cambio::hal {

/// The time every loop is written against. Times are nanoseconds on the clock's own epoch.
class Clock {
 public:
  virtual ~Clock() = default;
  /// Current time (ns). Thread-safe; real-time safe.
  virtual std::int64_t now_ns() const = 0;
  /// Blocks until now_ns() >= deadline_ns (returns at once if it already is). Real-time safe
  /// (no allocation); it blocks by design.
  virtual void sleep_until_ns(std::int64_t deadline_ns) = 0;
};

}  // namespace cambio::hal
