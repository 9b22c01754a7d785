#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "cambio/hal/clock.hpp"
#include "cambio/hal/loop.hpp"

namespace cambio::runtime::testing {

/// One update as seen by a loop: who ran, at what clock time, with which tick.
struct TraceEntry {
  std::string loop;
  std::int64_t clock_ns;
  std::uint64_t cycle;
  std::int64_t deadline_ns;
  bool operator==(const TraceEntry&) const = default;
};

/// A loop that appends each update to a shared trace (allocates: for ordering tests only).
class RecordingLoop final : public hal::Loop {
 public:
  RecordingLoop(std::string name, const hal::Clock& clock, std::vector<TraceEntry>& trace)
      : name_(std::move(name)), clock_(clock), trace_(trace) {}
  const std::string& name() const override { return name_; }
  void configure() override { ++configure_calls; }
  void activate() override { ++activate_calls; }
  hal::Status update(const hal::LoopTick& tick) noexcept override {
    trace_.push_back({name_, clock_.now_ns(), tick.cycle, tick.deadline_ns});
    return hal::Status::kOk;
  }
  void deactivate() noexcept override { ++deactivate_calls; }

  int configure_calls = 0;
  int activate_calls = 0;
  int deactivate_calls = 0;

 private:
  std::string name_;
  const hal::Clock& clock_;
  std::vector<TraceEntry>& trace_;
};

inline config::LoopConfig schedule(const std::string& name, double rate_hz, int priority = 0) {
  config::LoopConfig loop;
  loop.name = name;
  loop.rate_hz = rate_hz;
  loop.priority = priority;
  return loop;
}

}  // namespace cambio::runtime::testing
