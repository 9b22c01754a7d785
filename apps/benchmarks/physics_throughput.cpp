#include "physics_throughput.hpp"

#include <chrono>
#include <cmath>
#include <cstdint>
#include <memory>
#include <stdexcept>
#include <vector>

#include <mujoco/mujoco.h>

#include "bench_timing.hpp"
#include "cambio/sim/sim_backend.hpp"

namespace cambio::app {

namespace {

using Clock = std::chrono::steady_clock;

/// Every sim group of the rig, commanded along slow sines inside the joints' limits, so the
/// physics step works with moving arms and contacts, not a robot at rest.
struct Exerciser {
  std::vector<std::unique_ptr<hal::JointGroup>> groups;
  std::vector<std::vector<hal::JointCommand>> commands;

  void command(double t_s) {
    for (std::size_t g = 0; g < groups.size(); ++g) {
      const auto& info = groups[g]->info();
      for (std::size_t k = 0; k < info.joints.size(); ++k) {
        const auto& limits = info.limits[k];
        const double middle = 0.5 * (limits.min_position_rad + limits.max_position_rad);
        const double half = 0.3 * (limits.max_position_rad - limits.min_position_rad);
        commands[g][k] = {hal::CommandMode::kPosition,
                          middle + half * std::sin(0.7 * t_s + static_cast<double>(k))};
      }
      (void)groups[g]->write(commands[g]);
    }
  }
};

Exerciser make_exerciser(sim::SimBackend& backend, const config::RigConfig& rig) {
  Exerciser exerciser;
  for (const auto& group : rig.groups) {
    if (group.backend != sim::SimBackend::kName) continue;
    exerciser.groups.push_back(backend.make_joint_group(group.name));
    exerciser.commands.emplace_back(group.joints.size());
  }
  return exerciser;
}

/// Drives walk switch-on disabled -> operation enabled one transition per step: without this
/// the joints would hold still and the figure would measure an idle robot.
void enable_drives(sim::SimBackend& backend, Exerciser& exerciser) {
  for (auto& group : exerciser.groups) (void)group->request(hal::DriveRequest::kEnable);
  for (int k = 0; k < 3; ++k) (void)backend.physics().step_once(0);
}

}  // namespace

PhysicsFigure measure_physics(const config::RigConfig& rig, const config::SceneConfig& scene,
                              const hal::HardwareInfo& hardware, hal::Clock& clock,
                              double budget_s) {
  sim::SimBackend backend(rig, scene, hardware, hal::BackendContext{&clock});
  Exerciser exerciser = make_exerciser(backend, rig);
  backend.activate();
  auto& physics = backend.physics();
  enable_drives(backend, exerciser);
  const double dt = backend.world().timestep_s();
  std::uint64_t steps = 0;
  std::uint64_t contacts = 0;
  const auto start = Clock::now();
  double elapsed = 0.0;
  while (elapsed < budget_s) {
    for (int k = 0; k < 100; ++k) {
      // The joint loop writes at the physics rate, as under the executor.
      exerciser.command(static_cast<double>(steps) * dt);
      if (physics.step_once(static_cast<std::int64_t>(steps) * 1'000'000) != hal::Status::kOk) {
        throw std::runtime_error("the physics step faulted in scene " + scene.name);
      }
      contacts += static_cast<std::uint64_t>(backend.world().data()->ncon);
      ++steps;
    }
    elapsed = seconds_since(start);
  }
  return {static_cast<double>(steps) / elapsed,
          static_cast<double>(contacts) / static_cast<double>(steps), backend.world().model()->nq,
          backend.world().model()->nv};
}

}  // namespace cambio::app
