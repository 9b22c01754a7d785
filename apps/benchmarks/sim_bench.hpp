#pragma once

// `cambio sim-bench`'s measurement: in one run, the sim's physics steps per second for the full
// robot, the stereo frames per second of its camera pipeline, and, as the reference, a raw
// MuJoCo render-and-read loop of the same scene at the same resolution on the same GL context.

#include <optional>

#include "cambio/config/rig_config.hpp"
#include "cambio/config/scene_config.hpp"

namespace cambio::app {

/// An eye image size the command asks for instead of the rig's.
struct EyeSize {
  int width_px = 0;
  int height_px = 0;
};

struct SimBenchOptions {
  config::RigConfig rig;  ///< Has a stereo pair.
  std::optional<EyeSize> eye_size;
  config::SceneConfig physics_scene;  ///< For the physics figure (arms, contacts).
  config::SceneConfig camera_scene;   ///< For the robot-only physics and the camera figures.
  double seconds = 2.0;               ///< Wall time per measurement.
  bool json = false;                  ///< One JSON object instead of a table.
};

/// Measures and prints the figures. Returns the exit status: kExitBadInput (the issues printed)
/// when the sim cannot build the rig in a scene. Throws std::runtime_error when a physics step
/// faults or a camera grab fails.
int run_sim_bench(SimBenchOptions options);

}  // namespace cambio::app
