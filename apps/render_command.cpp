// `cambio render --config RIG --scene SCENE --out DIR [--set joints.<name>=<rad>]...`: renders
// the robot in a scene at a given pose: left.png and right.png through the eyes (the HAL camera
// pipeline), depth_left.png (16-bit, millimetres) and overview.png from a third-person camera.
// The rendering is in perception_runs/robot_render.hpp.
#include <cmath>
#include <numbers>
#include <span>
#include <string>
#include <vector>

#include "argument_parser.hpp"
#include "cambio/config/rig_loader.hpp"
#include "cambio/config/scene_config.hpp"
#include "cambio/config/shipped_config.hpp"
#include "command.hpp"
#include "config_errors.hpp"
#include "joint_pose.hpp"
#include "output_directory.hpp"
#include "robot_render.hpp"

namespace cambio::app {

namespace {

/// "<name>=<value>" with value in radians, or in degrees with a "deg" suffix.
JointPose parse_pose(const std::string& option, const std::string& text) {
  const auto equals = text.find('=');
  if (equals == std::string::npos || equals == 0 || equals + 1 == text.size()) {
    throw UsageError("render: " + option + " expects <joint>=<angle>, found '" + text + "'");
  }
  JointPose pose{text.substr(0, equals), 0.0};
  std::string value = text.substr(equals + 1);
  double scale = 1.0;
  if (value.size() > 3 && value.compare(value.size() - 3, 3, "deg") == 0) {
    scale = std::numbers::pi / 180.0;
    value.resize(value.size() - 3);
  } else if (value.size() > 3 && value.compare(value.size() - 3, 3, "rad") == 0) {
    value.resize(value.size() - 3);
  }
  std::size_t used = 0;
  try {
    pose.position_rad = std::stod(value, &used) * scale;
  } catch (const std::exception&) {
    used = 0;
  }
  if (used != value.size() || !std::isfinite(pose.position_rad)) {
    throw UsageError("render: " + option + " " + text + ": '" + text.substr(equals + 1) +
                     "' is not an angle (radians, or degrees with a deg suffix)");
  }
  return pose;
}

/// --set and --pose split into rig overrides and joint poses. `joints.<name>=<value>` (exactly
/// two components) is a pose; a longer key path (joints.neck_pan.max_velocity_rad_s=3)
/// overrides the rig. A joint entry is a map in the rig, so the two never collide.
void split_settings(const ArgumentParser& parser, std::vector<config::ConfigOverride>& overrides,
                    std::vector<JointPose>& poses) {
  for (const auto& text : parser.values("set")) {
    const auto equals = text.find('=');
    const std::string key = text.substr(0, equals);
    if (key.rfind("joints.", 0) == 0 && key.find('.', 7) == std::string::npos) {
      poses.push_back(parse_pose("--set", text.substr(7)));
    } else {
      overrides.push_back(config::parse_override(text));
    }
  }
  for (const auto& text : parser.values("pose")) poses.push_back(parse_pose("--pose", text));
}

}  // namespace

int run_render_command(std::span<const std::string> args) {
  ArgumentParser parser("render", "render the robot's eyes and an overview at a pose");
  parser.option("config", "RIG", "rig file, or a shipped rig's name (default: cambio)")
      .option("scene", "SCENE", "scene file, or a shipped scene's name (e.g. vergence)")
      .option("out", "DIR", "directory for left.png, right.png, depth_left.png, overview.png")
      .repeated_option("set", "KEY=VALUE",
                       "joints.<joint>=<rad> puts a joint at an angle (\"30deg\" for degrees); "
                       "any other key.path=value overrides the rig file")
      .repeated_option("pose", "JOINT=ANGLE", "the same as --set joints.<JOINT>=<ANGLE>")
      .option("mjcf", "FILE", "also write the generated MuJoCo model (MJCF) to FILE")
      .flag("no-shadows", "render the overview without shadows");
  if (!parser.parse(args)) return kExitOk;
  if (!parser.has("scene")) throw UsageError("render: --scene SCENE is required");
  // Checked and claimed before the work: a run that cannot write its pictures fails at once.
  OutputDirectory out(parser.value("out"), "render");

  std::vector<config::ConfigOverride> overrides;
  std::vector<JointPose> poses;
  split_settings(parser, overrides, poses);
  const auto rig_or_none = load_rig_or_report(
      config::resolve_config_argument("rigs", parser.value("config", "cambio")), overrides);
  if (!rig_or_none) return kExitBadInput;
  RenderOptions options;
  options.rig = *rig_or_none;
  try {
    options.scene =
        config::load_scene(config::resolve_config_argument("scenes", parser.value("scene")));
  } catch (const config::ConfigError& error) {
    report_config_error(error);
    return kExitBadInput;
  }
  if (!apply_joint_poses(options.rig, poses)) return kExitBadInput;
  if (parser.has("mjcf")) options.mjcf_path = parser.value("mjcf");
  options.shadows = !parser.flag_set("no-shadows");
  return render_robot(options, out);
}

}  // namespace cambio::app
