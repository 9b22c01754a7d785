// `cambio sim-bench [--json] [--width W --height H]`: in one run, the sim's physics steps per
// second for the full robot, the stereo frames per second of its camera pipeline (render, read
// back, flip, convert, noise: what Camera::grab does), and, as the reference, a raw MuJoCo
// render-and-read loop of the same scene at the same resolution on the same GL context. The
// measurement and the report are in benchmarks/sim_bench.hpp.
#include <iostream>
#include <optional>
#include <span>
#include <string>
#include <utility>

#include "argument_parser.hpp"
#include "cambio/config/rig_loader.hpp"
#include "cambio/config/scene_config.hpp"
#include "cambio/config/shipped_config.hpp"
#include "cambio/sim/sim_backend.hpp"
#include "command.hpp"
#include "config_errors.hpp"
#include "sim_bench.hpp"

namespace cambio::app {

namespace {

/// --width and --height, both or neither; nullopt keeps the rig's size.
std::optional<EyeSize> eye_size_option(const ArgumentParser& parser) {
  if (parser.has("width") != parser.has("height")) {
    throw UsageError("sim-bench: give both --width and --height");
  }
  if (!parser.has("width")) return std::nullopt;
  const config::Range side = config::Range::closed(16, sim::kMaxCameraSidePx);
  const std::string why = "the sim renders cameras up to " + std::to_string(sim::kMaxCameraSidePx) +
                          " px a side; below 16 px the figures measure overhead only";
  const long long width = parser.integer("width", 0, side, why);
  const long long height = parser.integer("height", 0, side, why);
  return EyeSize{static_cast<int>(width), static_cast<int>(height)};
}

/// --scene and --camera-scene into `options`; false (the issues printed) when one is invalid.
bool load_scenes_or_report(const ArgumentParser& parser, SimBenchOptions& options) {
  try {
    options.physics_scene = config::load_scene(
        config::resolve_config_argument("scenes", parser.value("scene", "table")));
    options.camera_scene = config::load_scene(
        config::resolve_config_argument("scenes", parser.value("camera-scene", "vergence")));
  } catch (const config::ConfigError& error) {
    report_config_error(error);
    return false;
  }
  return true;
}

}  // namespace

int run_sim_bench_command(std::span<const std::string> args) {
  ArgumentParser parser("sim-bench", "measure the sim's physics and camera throughput");
  parser.option("config", "RIG", "rig file or shipped rig name (default: cambio)")
      .option("scene", "SCENE", "scene for the physics figure (default: table: arms, contacts)")
      .option("camera-scene", "SCENE", "scene for the camera figures (default: vergence)")
      .option("width", "W",
              "eye image width in pixels, 16 to " + std::to_string(sim::kMaxCameraSidePx) +
                  " (default: the rig's)")
      .option("height", "H",
              "eye image height in pixels, 16 to " + std::to_string(sim::kMaxCameraSidePx) +
                  " (default: the rig's)")
      .option("seconds", "S", "wall time per measurement, up to 3600 (default 2)")
      .flag("json", "print one JSON object instead of a table");
  if (!parser.parse(args)) return kExitOk;
  SimBenchOptions options;
  options.seconds = parser.number("seconds", 2.0, config::Range{0.0, 3600.0, true, false},
                                  "the figures settle within seconds; an hour at most");
  options.json = parser.flag_set("json");

  auto rig_or_none = load_rig_or_report(
      config::resolve_config_argument("rigs", parser.value("config", "cambio")), {});
  if (!rig_or_none) return kExitBadInput;
  options.rig = *rig_or_none;
  if (!options.rig.stereo) {
    std::cerr << "cambio sim-bench: rig " << options.rig.name << " has no stereo pair to measure\n";
    return kExitBadInput;
  }
  options.eye_size = eye_size_option(parser);
  if (!load_scenes_or_report(parser, options)) return kExitBadInput;
  return run_sim_bench(std::move(options));
}

}  // namespace cambio::app
