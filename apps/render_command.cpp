// `cambio render --config RIG --scene SCENE --out DIR [--set joints.<name>=<rad>]...`: renders
// the robot in a scene at a given pose: left.png and right.png through the eyes (the HAL camera
// pipeline), depth_left.png (16-bit, millimetres) and overview.png from a third-person camera.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <numbers>
#include <string>
#include <vector>

#include "argument_parser.hpp"
#include "cambio/config/hardware_description.hpp"
#include "cambio/config/rig_loader.hpp"
#include "cambio/config/scene_config.hpp"
#include "cambio/config/shipped_config.hpp"
#include "cambio/hal/manual_clock.hpp"
#include "cambio/sim/mujoco_error.hpp"
#include "cambio/sim/sim_backend.hpp"
#include "command.hpp"
#include "config_errors.hpp"
#include "image_files.hpp"
#include "output_directory.hpp"

namespace cambio::app {

namespace {

constexpr int kOverviewWidthPx = 1280;
constexpr int kOverviewHeightPx = 960;

struct JointPose {
  std::string joint;
  double position_rad = 0.0;
};

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

std::vector<std::uint8_t> depth_mm_png(const std::vector<float>& depth_m, int width, int height) {
  std::vector<std::uint16_t> millimetres(depth_m.size());
  std::transform(depth_m.begin(), depth_m.end(), millimetres.begin(), [](float metres) {
    return static_cast<std::uint16_t>(std::clamp(std::lround(metres * 1000.0f), 0L, 65535L));
  });
  return encode_png16(millimetres, width, height);
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
  // Before any work: a run that cannot write its pictures is refused at once.
  // Checked and claimed before the work: a bad destination fails at once.
  OutputDirectory out(parser.value("out"), "render");

  // `joints.<name>=<value>` (exactly two components) is a pose; a longer key path
  // (joints.neck_pan.max_velocity_rad_s=3) overrides the rig. A joint entry is a map in the rig,
  // so the two never collide.
  std::vector<config::ConfigOverride> overrides;
  std::vector<JointPose> poses;
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

  const auto rig_or_none = load_rig_or_report(
      config::resolve_config_argument("rigs", parser.value("config", "cambio")), overrides);
  if (!rig_or_none) return kExitBadInput;
  config::RigConfig rig = *rig_or_none;
  config::SceneConfig scene;
  try {
    scene = config::load_scene(config::resolve_config_argument("scenes", parser.value("scene")));
  } catch (const config::ConfigError& error) {
    report_config_error(error);
    return kExitBadInput;
  }
  for (const auto& pose : poses) {
    auto it =
        std::find_if(rig.joints.begin(), rig.joints.end(),
                     [&](const config::JointConfig& joint) { return joint.name == pose.joint; });
    if (it == rig.joints.end()) {
      std::string known;
      for (const auto& joint : rig.joints) known += (known.empty() ? "" : ", ") + joint.name;
      std::cerr << "cambio render: no joint named '" << pose.joint << "' in rig " << rig.name
                << " (joints: " << known << ")\n";
      return kExitBadInput;
    }
    if (pose.position_rad < it->min_position_rad || pose.position_rad > it->max_position_rad) {
      std::cerr << "cambio render: " << pose.joint << " = " << pose.position_rad
                << " rad is outside its limits [" << it->min_position_rad << ", "
                << it->max_position_rad << "] rad\n";
      return kExitBadInput;
    }
    it->initial_position_rad = pose.position_rad;
  }

  const auto started = std::chrono::steady_clock::now();

  // Nothing runs in time here: the backend gets a clock that stays at zero.
  hal::ManualClock clock;
  sim::MjcfOptions mjcf_options;
  mjcf_options.offscreen_width_px = kOverviewWidthPx;
  mjcf_options.offscreen_height_px = kOverviewHeightPx;
  std::unique_ptr<sim::SimBackend> backend;
  try {
    backend = std::make_unique<sim::SimBackend>(rig, scene, config::hardware_description(rig),
                                                hal::BackendContext{&clock}, mjcf_options);
    // Made now, not at the first camera: the renderer refuses cameras larger than it can draw.
    (void)backend->renderer();
  } catch (const config::ConfigError& error) {
    report_config_error(error);
    return kExitBadInput;
  }
  if (parser.has("mjcf")) {
    std::ofstream mjcf(parser.value("mjcf"));
    mjcf << backend->world().mjcf();
    mjcf.close();
    if (mjcf.fail()) throw OutputError("--mjcf " + parser.value("mjcf") + ": could not write it");
  }
  // The pose is the initial state: render it as it is, without letting gravity act first.
  backend->activate();

  // The eyes through the HAL camera pipeline, exactly what perception would receive.
  std::vector<std::pair<std::string, std::string>> views;  // camera, file stem
  if (rig.stereo) {
    views = {{rig.stereo->left_camera, "left"}, {rig.stereo->right_camera, "right"}};
  } else {
    for (const auto& camera : rig.cameras) views.emplace_back(camera.name, camera.name);
  }
  for (const auto& [camera_name, stem] : views) {
    auto camera = backend->make_camera(camera_name);
    const auto& info = camera->info();
    hal::Image image(info.intrinsics.width_px, info.intrinsics.height_px, info.format);
    const hal::Status status = camera->grab(image);
    if (status != hal::Status::kOk) {
      std::cerr << "cambio render: camera " << camera_name << " returned " << hal::to_string(status)
                << "\n";
      return kExitFailure;
    }
    out.stage(stem + ".png", encode_png(image));
  }
  if (!views.empty()) {
    // Ground-truth depth of the left (or only) eye, in millimetres.
    const std::string& camera_name = views.front().first;
    hal::Image rgb;
    std::vector<float> depth_m;
    backend->ground_truth().render(camera_name, 0, 0, sim::ViewOptions{}, rgb, &depth_m);
    const std::string stem = rig.stereo ? "depth_left" : "depth_" + camera_name;
    out.stage(stem + ".png", depth_mm_png(depth_m, rgb.width_px, rgb.height_px));
  }
  {
    sim::ViewOptions view;
    view.shadows = !parser.flag_set("no-shadows");
    view.show_head = true;
    view.skybox = true;
    view.trilinear_textures = true;
    hal::Image overview;
    backend->ground_truth().render(sim::kOverviewCameraName, kOverviewWidthPx, kOverviewHeightPx,
                                   view, overview, nullptr);
    out.stage("overview.png", encode_png(overview));
  }
  const double seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - started).count();
  std::cout << "rendered rig " << rig.name << " in scene " << scene.name << " in "
            << static_cast<int>(seconds * 1000) << " ms\n"
            << "renderer: " << backend->renderer().description().summary() << "\n";
  out.commit();
  for (const auto& name : out.files()) std::cout << "  " << (out.path() / name).string() << "\n";
  return kExitOk;
}

}  // namespace cambio::app
