#pragma once

#include <cstdint>
#include <string>

#include "cambio/hal/status.hpp"

namespace cambio::hal {

/// What an executor tells a loop each cycle.
struct LoopTick {
  std::uint64_t cycle = 0;       ///< 0 on the first update after activate().
  std::int64_t deadline_ns = 0;  ///< The cycle's scheduled start on the executor's clock.
  std::int64_t now_ns = 0;       ///< When update() actually began (>= deadline_ns).
  double period_s = 0.0;
};

/// A fixed-rate piece of work: the joint loop, the control loop, the perception loop, the
/// physics step. Lifecycle (ros2_control's): configure (may throw, may allocate) -> activate ->
/// update ... update (noexcept, real-time safe: no allocation, no locks, no blocking) ->
/// deactivate. Executors call all of these from the loop's own thread.
class Loop {
 public:
  virtual ~Loop() = default;
  virtual const std::string& name() const = 0;
  virtual void configure() {}
  virtual void activate() {}
  virtual Status update(const LoopTick& tick) noexcept = 0;
  virtual void deactivate() noexcept {}
};

}  // namespace cambio::hal
