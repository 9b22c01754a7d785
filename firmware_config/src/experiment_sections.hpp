#pragma once

// Readers of an experiment file's sections (internal to firmware_config): the gaze task
// (gaze_task_loader.cpp) and how the run is judged (experiment_evaluation_loader.cpp). Like every
// MapReader client they record problems and return fallbacks; read_experiment throws them all.

#include <array>
#include <functional>
#include <string>
#include <vector>

#include "cambio/config/behaviour_config.hpp"
#include "cambio/config/experiment_evaluation.hpp"
#include "cambio/config/gaze_task_config.hpp"
#include "cambio/config/map_reader.hpp"
#include "cambio/config/rig_config.hpp"
#include "cambio/config/scene_config.hpp"

namespace cambio::config {

/// The experiment's scene as the sections see it: what names objects is checked against it.
struct SceneForSections {
  /// The loaded scene; nullptr when there is none or it could not be loaded.
  const SceneConfig* scene = nullptr;
  /// Whether the experiment names a scene (when it does and `scene` is null, the scene's own
  /// problems are already reported and object names are not checked again).
  bool named = false;
};

/// Checks that `name`, given at `key` of `map`, is an object of the scene; reports it at the key
/// with the scene's objects (and a "did you mean") if not, or if the experiment has no scene.
/// Returns the object, or nullptr.
const SceneObjectConfig* find_scene_object(MapReader& map, std::string_view key,
                                           const std::string& name, const SceneForSections& scene);

/// `gaze:` (all keys optional).
GazeTaskConfig read_gaze_task(MapReader gaze);

/// `arm:` (all keys optional).
ArmTaskConfig read_arm_task(MapReader arm);

/// The arm action of a `commands:` entry holding `reach`, `grasp` or `release` (which one is
/// `key`), with its `arm` for a reach.
ArmCommandConfig read_arm_command(MapReader& entry, std::string_view key);

/// A pixel target, kept to be checked against the dominant camera once the rig is loaded.
struct PendingPixelTarget {
  MapReader target;  ///< The action's map, holding `pixel`.
  std::array<double, 2> pixel_px{};
};

/// `commands:` of the experiment (at least one). `duration_s` <= 0 means the duration was itself
/// refused: at_s is then only checked to be >= 0. Object targets resolve against `scene`.
std::vector<GazeCommandConfig> read_gaze_commands(MapReader& experiment, double duration_s,
                                                  const SceneForSections& scene,
                                                  std::vector<PendingPixelTarget>& pixels);

/// Reports each pixel target outside `camera`'s image (the dominant eye's).
void check_pixel_targets(std::vector<PendingPixelTarget>& pixels, const CameraConfig& camera);

/// `behaviour:`; `resolve` turns a plugin's path into one relative to the experiment's folder.
BehaviourConfig read_behaviour(MapReader behaviour,
                               const std::function<std::string(const std::string&)>& resolve);

/// `evaluation:` (all keys optional); `duration_s` as for read_gaze_commands.
EvaluationConfig read_evaluation(MapReader evaluation, double duration_s,
                                 const SceneForSections& scene);

/// `goals:` of the experiment: metric name -> {max: v} or {min: v}, names from
/// kExperimentMetricNames.
std::vector<GoalConfig> read_goals(MapReader& experiment);

}  // namespace cambio::config
