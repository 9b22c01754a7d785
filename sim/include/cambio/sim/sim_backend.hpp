#pragma once

#include <cstdint>
#include <memory>
#include <set>
#include <string>
#include <string_view>
#include <vector>

#include "cambio/config/rig_config.hpp"
#include "cambio/config/scene_config.hpp"
#include "cambio/hal/backend_factory.hpp"
#include "cambio/hal/manual_clock.hpp"
#include "cambio/hal/monotonic_clock.hpp"
#include "cambio/sim/ground_truth.hpp"
#include "cambio/sim/mjcf_builder.hpp"
#include "cambio/sim/physics_loop.hpp"
#include "cambio/sim/renderer.hpp"
#include "cambio/sim/world.hpp"

namespace cambio::sim {

/// Registers the "sim" backend: the rig's sim groups, cameras and touch sensors served by one
/// MuJoCo world built from the rig and the scene named in BackendOptions::scene_path (a path,
/// or a shipped scene's name; empty: a bare floor).
void register_sim_backend(hal::BackendFactory& factory);

/// The simulator behind the HAL. One world, one physics loop (run it at the rate loops()
/// reports), one renderer shared by the cameras (created with the first camera or ground-truth
/// render, so a physics-only run needs no GL). Clock: a ManualClock for the lockstep executor,
/// CLOCK_MONOTONIC when options.realtime.
class SimBackend final : public hal::Backend {
 public:
  /// Builds the world (may throw ConfigError, MujocoError, std::runtime_error).
  SimBackend(const config::RigConfig& rig, const config::SceneConfig& scene,
             const hal::BackendOptions& options, const MjcfOptions& mjcf_options = {});
  ~SimBackend() override;

  std::unique_ptr<hal::JointGroup> make_joint_group(std::string_view group_name) override;
  std::unique_ptr<hal::Camera> make_camera(std::string_view camera_name) override;
  std::unique_ptr<hal::TouchSensor> make_touch_sensor(std::string_view sensor_name) override;
  hal::Clock& clock() override;
  std::vector<hal::BackendLoop> loops() override;

  /// The lockstep clock, or nullptr when running against the wall clock.
  hal::ManualClock* manual_clock() { return options_.realtime ? nullptr : &manual_clock_; }

  /// Evaluation only (tests, `cambio render`, experiment scoring); never hand it to control or
  /// perception.
  GroundTruth& ground_truth();
  World& world() { return *world_; }
  PhysicsLoop& physics() { return *physics_; }
  Renderer& renderer();

 private:
  config::RigConfig rig_;
  hal::BackendOptions options_;
  hal::ManualClock manual_clock_;
  hal::MonotonicClock monotonic_clock_;
  std::unique_ptr<World> world_;
  std::unique_ptr<PhysicsLoop> physics_;
  std::unique_ptr<Renderer> renderer_;
  std::unique_ptr<GroundTruth> ground_truth_;
  std::set<std::string, std::less<>> made_groups_;
  std::set<std::string, std::less<>> made_cameras_;
  std::uint64_t camera_streams_ = 0;
};

}  // namespace cambio::sim
