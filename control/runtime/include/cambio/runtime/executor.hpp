#pragma once

#include <atomic>
#include <cstdint>
#include <deque>
#include <functional>
#include <string>
#include <vector>

#include "cambio/hal/clock.hpp"
#include "cambio/runtime/live_loop_counters.hpp"
#include "cambio/runtime/loop_statistics.hpp"
#include "cambio/runtime/scheduled_loop.hpp"

namespace cambio::runtime {

/// What the application needs of either executor. The executor owns the run's one clock and
/// hands it out (clock()) before anything is built, so every backend and loop stamps with it.
class Executor {
 public:
  /// Called from the thread that called run(), about every 0.1 s of run time, with the run
  /// time done so far (s).
  using Progress = std::function<void(double done_s)>;

  virtual ~Executor() = default;

  /// The run's clock. Valid for the executor's lifetime.
  virtual hal::Clock& clock() = 0;
  /// Adds a loop before run(). Throws std::invalid_argument for a null loop or a bad schedule.
  virtual void add_loop(ScheduledLoop loop) = 0;
  /// configure() and activate() every loop (rethrowing the first exception after stopping the
  /// others), runs until `stop` is set or `duration_ns` of the clock passed, then deactivates
  /// every loop. Returns the run time done (ns).
  virtual std::int64_t run(const std::atomic<bool>& stop, std::int64_t duration_ns,
                           const Progress& progress) = 0;
  /// Per loop, in add_loop() order, after run().
  virtual const std::vector<LoopStatistics>& statistics() const = 0;

  /// Per loop, in add_loop() order, while run() runs (any one thread; each read restarts the
  /// maxima): cycles, overruns, the worst wake-up latency and update time since the last read.
  std::vector<LiveLoopSample> live_statistics();

 protected:
  /// The executors' add_loop() registers each loop here, before run().
  void add_live_loop(std::string name, double rate_hz);
  LiveLoopCounters& live(std::size_t loop) { return live_[loop]; }

 private:
  std::deque<LiveLoopCounters> live_;  // Atomics do not move: a deque keeps them in place.
  std::vector<LiveLoopSample> live_names_;
};

/// Checks a schedule the way both executors do; throws std::invalid_argument naming the loop.
void validate(const ScheduledLoop& loop, const char* executor_name);

}  // namespace cambio::runtime
