#pragma once

#include <algorithm>
#include <array>
#include <cstdint>
#include <exception>
#include <string>
#include <string_view>

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

  /// True for a loop whose update() must allocate, which is then no real-time loop: a user's
  /// behaviour, the evaluation's trace recorder, the camera loop grabbing the sim's rendered
  /// cameras (Camera::grab_allocates). Executors still count and report its allocations but
  /// exempt it from the zero-allocation gate. Every control loop must not allocate after
  /// configure().
  virtual bool allocates_in_update() const { return false; }

  /// The last fault update() reported (empty if none). Read it from the loop's thread or after
  /// the executor stopped.
  std::string_view fault_message() const { return std::string_view(fault_message_.data()); }
  std::uint64_t fault_count() const { return fault_count_; }

 protected:
  /// Records why this cycle failed (truncated to a fixed buffer: no allocation) and returns
  /// kFault for update() to return.
  Status report_fault(std::string_view message) noexcept {
    const std::size_t n = std::min(message.size(), fault_message_.size() - 1);
    std::copy_n(message.data(), n, fault_message_.data());
    fault_message_[n] = '\0';
    ++fault_count_;
    return Status::kFault;
  }

  /// For a loop whose work may throw (a library call): runs `work` and turns any exception into
  /// a reported fault of this loop, so update() stays noexcept and never reaches std::terminate.
  template <class Work>
  Status guarded(Work&& work) noexcept {
    try {
      return work();
    } catch (const std::exception& error) {
      return report_fault(error.what());
    } catch (...) {
      return report_fault("unknown exception");
    }
  }

 private:
  std::array<char, 256> fault_message_{};
  std::uint64_t fault_count_ = 0;
};

}  // namespace cambio::hal
