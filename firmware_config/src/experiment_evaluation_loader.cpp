// How an experiment's run is judged: `evaluation:` and `goals:`.
#include <algorithm>
#include <string>

#include "experiment_sections.hpp"
#include "format.hpp"

namespace cambio::config {

EvaluationConfig read_evaluation(MapReader evaluation, double duration_s,
                                 const SceneForSections& scene) {
  // Keys left out keep EvaluationConfig's member initialisers, the one place of the defaults.
  EvaluationConfig config;
  if (evaluation.has("target_object")) {
    config.target_object = evaluation.text("target_object");
    // With no scene the name cannot be checked, and nothing in the run can be looked at by it.
    if (scene.named) find_scene_object(evaluation, "target_object", config.target_object, scene);
  }
  if (evaluation.has("key_frames_s")) {
    const Range within_run =
        duration_s > 0.0 ? Range::closed(0.0, duration_s).because("the experiment's duration_s")
                         : Range::non_negative();
    config.key_frames_s = evaluation.numbers("key_frames_s", within_run);
  }
  if (auto settle = evaluation.optional_map("settle")) {
    SettleConfig& s = config.settle;
    s.disparity_px = settle->number_or("disparity_px", s.disparity_px, Range::positive());
    s.gaze_error_rad = settle->angle_rad_or("gaze_error", s.gaze_error_rad, Range::positive());
    settle->finish();
  }
  config.pursuit_catch_up_s =
      evaluation.number_or("pursuit_catch_up_s", config.pursuit_catch_up_s, Range::non_negative());
  config.visit_objects = evaluation.strings_or("visit_objects", {});
  for (const std::string& name : config.visit_objects) {
    find_scene_object(evaluation, "visit_objects", name, scene);
  }
  config.visit_dwell_s =
      evaluation.number_or("visit_dwell_s", config.visit_dwell_s, Range::positive());
  evaluation.finish();
  return config;
}

std::vector<GoalConfig> read_goals(MapReader& experiment) {
  const std::vector<std::string> metrics(kExperimentMetricNames.begin(),
                                         kExperimentMetricNames.end());
  std::vector<GoalConfig> goals;
  for (auto& [name, bounds] : experiment.named_maps("goals")) {
    const bool known = std::find(metrics.begin(), metrics.end(), name) != metrics.end();
    if (!known) {
      std::string message = "unknown metric " + in_quotes(name);
      if (const auto suggestion = closest_name(name, metrics)) {
        message += "; did you mean " + in_quotes(*suggestion) + "?";
      } else {
        message += "; expected one of " + join(metrics);
      }
      bounds.error("", message);
    }
    GoalConfig goal;
    goal.metric = name;
    const bool has_max = bounds.has("max");
    const bool has_min = bounds.has("min");
    goal.bound = has_max ? GoalBound::kMax : GoalBound::kMin;
    goal.value = bounds.number_or(has_max ? "max" : "min", 0.0);
    if (has_max && has_min) {
      bounds.error("min", "expected either max or min, found both");
    } else {
      // The other is looked up too, so that a misspelt one is offered the right name.
      bounds.number_or(has_max ? "min" : "max", 0.0);
      if (!has_max && !has_min) {
        bounds.error("", std::string(kMissingKey) + " (expected max or min: {max: v} or {min: v})");
      }
    }
    bounds.finish();
    if (known && (has_max != has_min)) goals.push_back(goal);
  }
  return goals;
}

}  // namespace cambio::config
