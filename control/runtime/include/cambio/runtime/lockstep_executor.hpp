#pragma once

#include <cstdint>
#include <vector>

#include "cambio/hal/manual_clock.hpp"
#include "cambio/runtime/executor.hpp"
#include "cambio/runtime/loop_statistics.hpp"
#include "cambio/runtime/scheduled_loop.hpp"

namespace cambio::runtime {

/// Runs every loop on one thread against its own ManualClock: it advances simulated time to the
/// earliest pending deadline and runs that loop, then repeats. Loops due at the same instant run
/// in descending priority, then in the order given. Deterministic (no wall clock involved) and
/// as fast as the loops allow. Wake-up latency is 0 by construction; execution time is measured
/// on CLOCK_MONOTONIC for information only.
class LockstepExecutor final : public Executor {
 public:
  explicit LockstepExecutor(std::vector<ScheduledLoop> loops = {}, std::int64_t start_ns = 0);

  hal::ManualClock& clock() override { return clock_; }
  void add_loop(ScheduledLoop loop) override;
  std::int64_t run(const std::atomic<bool>& stop, std::int64_t duration_ns,
                   const Progress& progress) override;
  const std::vector<LoopStatistics>& statistics() const override { return stats_; }

  /// The steps of run(), for tests that drive time themselves.
  /// Calls configure() then activate() on every loop; may throw. Allocates everything.
  void configure();
  /// Runs all cycles whose deadline is < end_ns. Real-time safe (no allocation).
  void run_until_ns(std::int64_t end_ns);
  /// Calls deactivate() on every loop and collects their fault messages.
  void deactivate();

 private:
  hal::ManualClock clock_;
  std::vector<ScheduledLoop> loops_;
  std::vector<LoopStatistics> stats_;
  std::vector<std::uint64_t> next_cycle_;
  std::int64_t start_ns_ = 0;
  bool configured_ = false;
};

}  // namespace cambio::runtime
