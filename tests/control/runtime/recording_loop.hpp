#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "cambio/hal/clock.hpp"
#include "cambio/hal/loop.hpp"
#include "cambio/runtime/scheduled_loop.hpp"

namespace cambio::runtime::testing {

/// One update as seen by a loop: who ran, at what clock time, with which tick.
struct TraceEntry {
  std::string loop;
  std::int64_t clock_ns;
  std::uint64_t cycle;
  std::int64_t deadline_ns;
  bool operator==(const TraceEntry&) const = default;
};

/// A loop that appends each update to a shared trace. The trace's capacity is reserved up front
/// (the owner calls trace.reserve()), so update() never allocates; a full trace is a reported
/// fault, never a reallocation inside noexcept code. `work` runs inside each update (a test can
/// burn wall time there).
class RecordingLoop final : public hal::Loop {
 public:
  RecordingLoop(std::string name, const hal::Clock& clock, std::vector<TraceEntry>& trace)
      : name_(std::move(name)), clock_(clock), trace_(trace) {}
  const std::string& name() const override { return name_; }
  void configure() override { ++configure_calls; }
  void activate() override { ++activate_calls; }
  hal::Status update(const hal::LoopTick& tick) noexcept override {
    if (work) work();
    if (trace_.size() == trace_.capacity()) return report_fault("trace full");
    // The name is copied into a string that fits the small-string buffer (no allocation).
    trace_.push_back({name_, clock_.now_ns(), tick.cycle, tick.deadline_ns});
    return hal::Status::kOk;
  }
  void (*work)() = nullptr;
  void deactivate() noexcept override { ++deactivate_calls; }

  int configure_calls = 0;
  int activate_calls = 0;
  int deactivate_calls = 0;

 private:
  std::string name_;
  const hal::Clock& clock_;
  std::vector<TraceEntry>& trace_;
};

inline LoopSchedule schedule(double rate_hz, int priority = 0) {
  LoopSchedule loop;
  loop.rate_hz = rate_hz;
  loop.priority = priority;
  return loop;
}

}  // namespace cambio::runtime::testing
