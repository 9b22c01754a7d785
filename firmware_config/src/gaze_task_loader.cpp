// The gaze task of an experiment file: `gaze:` and `commands:`.
#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <optional>
#include <string>
#include <utility>

#include "cambio/config/command_target_bounds.hpp"
#include "experiment_sections.hpp"
#include "format.hpp"

namespace cambio::config {

namespace {

constexpr double kPi = std::numbers::pi;

struct ActionName {
  std::string_view key;
  GazeAction action;
};
constexpr std::array<ActionName, 4> kActions{{
    {"fixate", GazeAction::kFixate},
    {"saccade", GazeAction::kSaccade},
    {"pursue", GazeAction::kPursue},
    {"hold", GazeAction::kHold},
}};

/// The keys that give a target; one at most per command.
constexpr std::array<std::string_view, 5> kTargetKeys{"object", "point_m", "pixel", "angles_deg",
                                                      "angles_rad"};

/// Two numbers at `key` (which the map holds), each within `each`; nullopt after reporting.
std::optional<std::array<double, 2>> read_pair(MapReader& map, std::string_view key,
                                               std::string_view what, Range each) {
  const std::vector<double> values = map.numbers(key, each);
  if (values.size() == 2) return std::array<double, 2>{values[0], values[1]};
  // numbers() reported a value that is not a number or is out of range, and returned nothing.
  if (!values.empty()) {
    map.error(key, "expected " + std::string(what) + ", found " + std::to_string(values.size()) +
                       " numbers");
  }
  return std::nullopt;
}

/// The position of `object` when the run starts (t = 0): a waypoint path starts on its first
/// waypoint, every other motion on the object's pose (sim/src/object_motion.cpp).
std::array<double, 3> initial_centre(const SceneObjectConfig& object) {
  if (object.motion.kind == MotionKind::kWaypoints && !object.motion.waypoints.empty()) {
    return object.motion.waypoints.front().xyz_m;
  }
  return object.pose.xyz_m;
}

/// The target of one command's action map `action` (named `action_key`).
GazeTargetConfig read_target(MapReader& action, std::string_view action_key, bool needs_target,
                             const SceneForSections& scene,
                             std::vector<PendingPixelTarget>& pixels) {
  std::vector<std::string_view> given;
  for (const auto key : kTargetKeys) {
    if (action.has(key)) given.push_back(key);
  }
  GazeTargetConfig target;
  if (!needs_target) {
    for (const auto key : given) {
      action.error(key,
                   std::string(action_key) + " takes no target (" +
                       (action_key == "pursue" ? "pursuit follows what the dominant eye fixates"
                                               : "hold keeps the head where it is") +
                       "), found " + std::string(key));
    }
    return target;
  }
  if (given.empty()) {
    action.error("", std::string(kMissingKey) + " (expected a target: one of object, point_m, " +
                         "pixel, angles_deg)");
  }
  for (std::size_t i = 1; i < given.size(); ++i) {
    action.error(given[i], "expected one target, found " + std::string(given[0]) + " and " +
                               std::string(given[i]));
  }
  if (given.empty()) return target;
  // Only the first target is read: the others are already refused.
  const std::string_view key = given[0];
  if (key == "object") {
    target.object = action.text("object");
    if (const SceneObjectConfig* object =
            find_scene_object(action, "object", target.object, scene)) {
      target.kind = GazeTargetKind::kPoint;
      target.point_W_m = initial_centre(*object);
    }
  } else if (key == "point_m") {
    target.kind = GazeTargetKind::kPoint;
    target.point_W_m = action.vector3(
        "point_m", Range::closed(-kMaxTargetCoordinate_m, kMaxTargetCoordinate_m)
                       .because("a point the eyes can fixate, within a kilometre of the robot"));
  } else if (key == "pixel") {
    if (const auto pixel = read_pair(action, "pixel", "[u, v] in pixels", Range::non_negative())) {
      target.kind = GazeTargetKind::kPixel;
      target.pixel_px = *pixel;
      pixels.push_back({action, *pixel});
    }
  } else {
    const bool degrees = key == "angles_deg";
    const double scale = degrees ? kPi / 180.0 : 1.0;
    // At a quarter turn the image plane has no direction for the displacement (and beyond it
    // the gaze loop's tan would turn it back).
    const Range below_quarter_turn =
        Range::closed(-kMaxGazeDisplacementRad / scale, kMaxGazeDisplacementRad / scale)
            .because("a displacement of the gaze, less than a quarter turn");
    if (const auto angles = read_pair(action, key, "[pan, tilt]", below_quarter_turn)) {
      target.kind = GazeTargetKind::kAngles;
      // Multiply before dividing, as MapReader does, so that whole degrees give the closed form.
      target.angles_rad =
          degrees ? std::array<double, 2>{(*angles)[0] * kPi / 180.0, (*angles)[1] * kPi / 180.0}
                  : *angles;
    }
  }
  return target;
}

}  // namespace

const SceneObjectConfig* find_scene_object(MapReader& map, std::string_view key,
                                           const std::string& name, const SceneForSections& scene) {
  if (name.empty()) return nullptr;  // Already reported by text().
  if (!scene.named) {
    map.error(key, "expected the name of a scene object, found " + in_quotes(name) +
                       ", but the experiment names no scene (experiment.scene)");
    return nullptr;
  }
  if (scene.scene == nullptr) return nullptr;  // The scene's own problems are reported.
  if (const SceneObjectConfig* object = scene.scene->find_object(name)) return object;
  std::vector<std::string> names;
  for (const auto& object : scene.scene->objects) names.push_back(object.name);
  std::string message = "unknown object " + in_quotes(name) + " (scene " +
                        in_quotes(scene.scene->name) + " in " + scene.scene->source_file +
                        (names.empty() ? " has no objects)" : " has " + join(names) + ")");
  if (const auto suggestion = closest_name(name, names)) {
    message += "; did you mean " + in_quotes(*suggestion) + "?";
  }
  map.error(key, message);
  return nullptr;
}

GazeTaskConfig read_gaze_task(MapReader gaze) {
  // Keys left out keep GazeTaskConfig's member initialisers, the one place of the defaults.
  GazeTaskConfig config;
  config.dominant_eye = gaze.choice_or("dominant_eye", {"left", "right"},
                                       std::string(hal::to_string(config.dominant_eye))) == "right"
                            ? hal::Eye::kRight
                            : hal::Eye::kLeft;
  config.fixation_gain_per_s =
      gaze.number_or("fixation_gain", config.fixation_gain_per_s, Range::positive());
  config.neck_rule_rad =
      gaze.angle_rad_or("neck_rule", config.neck_rule_rad, {0.0, kPi / 2.0, true, false});
  config.default_depth_m =
      gaze.number_or("default_depth_m", config.default_depth_m, Range::positive());
  if (auto vergence = gaze.optional_map("vergence")) {
    GazeVergenceConfig& v = config.vergence;
    v.enabled = vergence->boolean_or("enabled", v.enabled);
    v.gain = vergence->number_or("gain", v.gain, {0.0, 1.0, true, false});
    v.min_confidence = vergence->number_or("min_confidence", v.min_confidence, Range::closed(0, 1));
    v.max_step_rad = vergence->angle_rad_or("max_step", v.max_step_rad, Range::positive());
    vergence->finish();
  }
  if (auto saccade = gaze.optional_map("saccade")) {
    config.saccade.predictive_vergence =
        saccade->boolean_or("predictive_vergence", config.saccade.predictive_vergence);
    saccade->finish();
  }
  if (auto pursuit = gaze.optional_map("pursuit")) {
    GazePursuitConfig& p = config.pursuit;
    p.position_gain_per_s =
        pursuit->number_or("position_gain", p.position_gain_per_s, Range::positive());
    p.velocity_gain = pursuit->number_or("velocity_gain", p.velocity_gain, Range::closed(0, 2));
    pursuit->finish();
  }
  gaze.finish();
  return config;
}

std::vector<GazeCommandConfig> read_gaze_commands(MapReader& experiment, double duration_s,
                                                  const SceneForSections& scene,
                                                  std::vector<PendingPixelTarget>& pixels) {
  std::vector<GazeCommandConfig> commands;
  if (!experiment.has("commands")) {
    experiment.error("commands",
                     std::string(kMissingKey) + " (expected at least one command for task gaze)");
    return commands;
  }
  std::vector<MapReader> entries = experiment.map_list("commands");
  if (entries.empty()) {
    experiment.error("commands", "expected at least one command for task gaze, found none");
  }
  const Range at_range = duration_s > 0.0
                             ? Range::closed(0.0, duration_s).because("the experiment's duration_s")
                             : Range::non_negative();
  double previous_s = 0.0;
  for (auto& entry : entries) {
    GazeCommandConfig command;
    // A refused at_s is not compared with its neighbours (its fallback would be).
    bool at_valid = false;
    if (entry.has("at_s")) {
      command.at_s = entry.number_or("at_s", std::numeric_limits<double>::quiet_NaN(), at_range);
      at_valid = !std::isnan(command.at_s);
      if (!at_valid) command.at_s = previous_s;
    } else {
      command.at_s = entry.number("at_s", at_range);
    }
    if (at_valid && command.at_s < previous_s) {
      entry.error("at_s", "expected commands in time order, found at_s " +
                              format_number(command.at_s) + " after " + format_number(previous_s));
    }
    previous_s = std::max(previous_s, command.at_s);
    // Every action key is looked up, so that a misspelt one is offered the right name.
    std::optional<MapReader> action;
    std::string_view action_key;
    for (const auto& [key, kind] : kActions) {
      auto map = entry.optional_map(key);
      if (!map) continue;
      if (action) {
        entry.error(key, "expected one action per command, found " + std::string(action_key) +
                             " and " + std::string(key));
        continue;
      }
      action = std::move(map);
      action_key = key;
      command.action = kind;
    }
    // An arm action instead (the arms' loop takes it): one action per entry all the same.
    for (const std::string_view key : {"reach", "grasp", "release"}) {
      if (!entry.has(key)) {
        (void)entry.text_or(key, {});  // Looked up, so that a misspelt one is offered it.
        continue;
      }
      if (action || command.arm) {
        entry.error(key, "expected one action per command, found " + std::string(action_key) +
                             " and " + std::string(key));
        continue;
      }
      command.arm = read_arm_command(entry, key);
      action_key = key;
    }
    if (entry.has("arm") && !(command.arm && command.arm->action == ArmActionConfig::kReach)) {
      entry.error("arm",
                  "expected arm only beside reach (grasp and release name their arm as "
                  "their value)");
    }
    (void)entry.text_or("arm", {});  // Read (reported above if misplaced), or offered if misspelt.
    if (!action && !command.arm) {
      entry.error("", std::string(kMissingKey) +
                          " (expected one action: fixate, saccade, pursue, hold, reach, grasp or "
                          "release)");
    } else if (action) {
      const bool needs_target =
          command.action == GazeAction::kFixate || command.action == GazeAction::kSaccade;
      command.target = read_target(*action, action_key, needs_target, scene, pixels);
      command.verge = action->boolean_or("verge", command.verge);
      // Look every target key up, so that a misspelt one is offered the right name.
      for (const auto key : kTargetKeys) {
        if (!action->has(key)) action->text_or(key, {});
      }
      action->finish();
    }
    entry.finish();
    commands.push_back(std::move(command));
  }
  return commands;
}

void check_pixel_targets(std::vector<PendingPixelTarget>& pixels, const CameraConfig& camera) {
  for (auto& pending : pixels) {
    const double max_u = camera.width_px - 1;
    const double max_v = camera.height_px - 1;
    const auto [u, v] = pending.pixel_px;
    if (u > max_u || v > max_v) {
      pending.target.error(
          "pixel", "expected a pixel of the dominant eye's " + std::to_string(camera.width_px) +
                       " x " + std::to_string(camera.height_px) + " image (camera " +
                       in_quotes(camera.name) + "): u in [0, " + format_number(max_u) +
                       "], v in [0, " + format_number(max_v) + "], found [" + format_number(u) +
                       ", " + format_number(v) + "]");
    }
  }
}

}  // namespace cambio::config
