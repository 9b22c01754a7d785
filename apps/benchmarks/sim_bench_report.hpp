#pragma once

// What sim-bench prints: one JSON object (--json) or a table for people.

#include <optional>
#include <string>
#include <vector>

#include "cambio/config/rig_config.hpp"
#include "cambio/sim/egl_context.hpp"
#include "cambio/sim/egl_devices.hpp"
#include "camera_throughput.hpp"
#include "physics_throughput.hpp"

namespace cambio::app {

struct SimBenchFigures {
  std::string rig_name;
  std::string physics_scene;  ///< The scene of `physics` (arms, contacts).
  std::string camera_scene;   ///< The scene of `robot_only` and `cameras`.
  PhysicsFigure physics;
  PhysicsFigure robot_only;
  CameraFigures cameras;
  /// The rig's foveation, measured as `cameras.foveated_fps`; nullopt when its eyes have none.
  std::optional<config::SimFoveationConfig> foveation;
  sim::RendererDescription rendering;
  /// What there was to render on; nullopt, with `devices_problem` saying why, when the EGL
  /// devices could not be listed.
  std::optional<std::vector<sim::EglDevice>> devices;
  std::string devices_problem;
};

/// The figures as one JSON object on stdout; a devices problem goes to stderr.
void print_sim_bench_json(const SimBenchFigures& figures);

/// The figures as a table on stdout.
void print_sim_bench_table(const SimBenchFigures& figures);

}  // namespace cambio::app
