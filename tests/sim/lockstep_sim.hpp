#pragma once

#include <cstdint>
#include <memory>

#include "cambio/runtime/lockstep_executor.hpp"
#include "sim_test_support.hpp"

namespace cambio::sim::testing {

/// The sim wired as an application wires it under the lockstep executor: the executor (which
/// owns the run's ManualClock) first, then the backend on that clock, the backend's physics loop
/// added to the executor at its rate.
struct LockstepSim {
  runtime::LockstepExecutor executor;  // Declared first: the backend holds its clock.
  std::unique_ptr<SimBackend> backend;

  LockstepSim(const config::RigConfig& rig, const config::SceneConfig& scene,
              std::uint64_t seed = 0)
      : backend(make_sim(rig, scene, executor.clock(), seed)) {
    for (const auto& loop : backend->loops()) {
      executor.add_loop({loop.loop, runtime::LoopSchedule{loop.rate_hz, loop.priority, -1,
                                                          runtime::OverrunPolicy::kSkip}});
    }
  }

  void add_loop(hal::Loop& loop, double rate_hz) {
    executor.add_loop(
        {&loop, runtime::LoopSchedule{rate_hz, 0, -1, runtime::OverrunPolicy::kSkip}});
  }
  /// The application's order: the backend configured and activated, then every loop.
  void start() {
    backend->configure();
    backend->activate();
    executor.configure();
  }
  void run_for_s(double seconds) {
    executor.run_until_ns(executor.clock().now_ns() + static_cast<std::int64_t>(seconds * 1e9));
  }
  void stop() {
    executor.deactivate();
    backend->deactivate();
  }
};

}  // namespace cambio::sim::testing
