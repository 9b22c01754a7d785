#pragma once

// `cambio render`'s run: the robot in a scene at a given pose, rendered into an output directory:
// left.png and right.png through the eyes (the HAL camera pipeline), depth_left.png (16-bit,
// millimetres) and overview.png from a third-person camera.

#include <optional>
#include <string>

#include "cambio/config/rig_config.hpp"
#include "cambio/config/scene_config.hpp"
#include "output_directory.hpp"

namespace cambio::app {

struct RenderOptions {
  config::RigConfig rig;  ///< Its joints' initial positions are the pose rendered.
  config::SceneConfig scene;
  std::optional<std::string> mjcf_path;  ///< Also write the generated MuJoCo model there.
  bool shadows = true;                   ///< In the overview.
};

/// Renders and stages the pictures in `out`, commits them and prints what was rendered, on what,
/// and the files written. Returns the exit status: kExitBadInput (the issues printed) when the
/// sim cannot build the rig in the scene, kExitFailure when a camera fails. Throws OutputError
/// when a file cannot be written.
int render_robot(const RenderOptions& options, OutputDirectory& out);

}  // namespace cambio::app
