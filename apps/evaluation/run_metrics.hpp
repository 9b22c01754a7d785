#pragma once

// An experiment's figures of merit, computed from its recorded Trace (run_trace.hpp) and the
// times of the gaze commands it sent, and the goals checked against them (issue 9's "Goals").
//
// Definitions (a trace row is one control-rate sample; "the end" is the last row):
//  final_disparity_px      |disparity| of the last row with a valid measurement.
//  true_gaze_error_deg     TraceRow::true_gaze_error_deg (the larger eye's) of the last row
//                          that has one.
//  settle_time_s           From the last fixate or saccade command (the first row when there is
//                          none) to the first row from which, to the end, every row has a valid
//                          |disparity| <= settle_disparity_px and a true gaze error <=
//                          settle_gaze_error_deg. Absent if the last row does not. Runs that
//                          never measure disparity settle on the gaze error alone.
//  saccade_duration_s      For the last saccade command at t0: the dominant eye moves from the
//                          first row at or after t0 where the gaze loop reports saccade_active
//                          or the dominant eye's true pan speed exceeds stop_speed_rad_s; it
//                          has stopped at the first row after that where saccade_active is off
//                          and the speed (backward difference of the true pan between rows) is
//                          at most stop_speed_rad_s. Duration = stop time - t0.
//  max_vergence_error_during_saccade_deg
//                          The largest verging-eye true gaze error over rows in [t0, stop].
//  reverge_time_s          From the stop to the first row from which every row until the next
//                          command (or the end) has a valid |disparity| <= reverge_disparity_px.
//  pursuit_rms_error_deg   RMS of the dominant eye's true gaze error over the rows of the last
//                          pursue command's period (its time + pursuit_catch_up_s to the next
//                          command or the end).
//  max_believed_vs_true_joint_error_rad
//                          max |believed - true| over rows and joints that have both.
//  final_/max_believed_vs_true_fixation_error_m
//                          TraceRow::fixation_error_m of the last row that has one / its max,
//                          over the rows from the first that meets the settle thresholds (as
//                          max_verging_gaze_error_visible_deg): before the eyes verge their axes
//                          meet far away or not at all.
//  final_max_abs_eye_pan_deg
//                          max(|true pan|) of the two eyes' pan joints at the last row.
//  max_verging_gaze_error_visible_deg
//                          The largest verging-eye error over rows not target_occluded, from
//                          the first row that meets the settle thresholds (first reached, not
//                          held: a distractor crossing later must not move the start).
//  target_occluded_s       Total time of rows marked target_occluded (each row lasts until the
//                          next; the last as long as the one before).
//  objects_visited         How many of the evaluation's visit_objects were visited: the
//                          dominant eye's true optical axis met the object (TraceRow::
//                          axis_object) in consecutive rows, none with saccade_active, spanning
//                          at least visit_dwell_s (object_visit_times).
//  all_objects_visited_s   When the last of them was first visited (the row completing its
//                          dwell); absent unless every one was.
//  time_to_touch_s         The newest accepted reach (Trace::reach): from its command to the
//                          arm's touch sensor stopping it (ArmStatus::touch_ns).
//  touch_position_error_m  At that touch: |the gap| between the gripper's true contact geometry
//                          (the fingers and palm its touch sensor covers) and the target
//                          object's surface (evaluation.target_object): a touch of something
//                          else, or a late one, shows here.
//  estimated_target_error_m
//                          At the reach command: the distance from the target the arm took (for
//                          reach: fixation, the head's stereo estimate: where its believed
//                          optical axes meet) to the point where the dominant eye's true optical
//                          axis meets the target object's surface.
// A metric that does not apply to a run (no saccade command, no disparity, no target...) is
// absent, with the reason in RunMetrics::absent.

#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "cambio/config/experiment_evaluation.hpp"
#include "json_output.hpp"
#include "run_trace.hpp"

namespace cambio::app {

/// The metric names, in summary.json order: the config's list, so goals are checked at load time
/// against the same names.
inline constexpr const auto& kMetricNames = config::kExperimentMetricNames;

/// A gaze command the run sent, at its time since the start.
struct CommandTime {
  double time_s = 0.0;
  control::GazeAction action = control::GazeAction::kHold;
};

struct MetricInputs {
  std::vector<CommandTime> commands;  ///< In time order.
  double settle_disparity_px = 0.5;
  double settle_gaze_error_deg = 0.1;
  double reverge_disparity_px = 1.0;
  double pursuit_catch_up_s = 0.5;
  /// The dominant eye's true pan speed below which it has stopped (0.05 rad/s, about 3 deg/s:
  /// far above the sim's motion noise over one control period, far below a saccade's speed).
  double stop_speed_rad_s = 0.05;
  /// How long the axis must rest on an object for a visit (objects_visited).
  double visit_dwell_s = 0.2;
};

/// The metrics present for a run, in kMetricNames order, and why the others are absent.
struct RunMetrics {
  std::vector<std::pair<std::string, double>> values;
  std::vector<std::pair<std::string, std::string>> absent;

  std::optional<double> find(std::string_view name) const;
  /// Why `name` is absent ("" if it is present or unknown).
  std::string absent_reason(std::string_view name) const;
};

/// Throws std::invalid_argument for commands out of time order or non-positive thresholds.
RunMetrics compute_metrics(const Trace& trace, const MetricInputs& inputs);

/// For each of trace.visit_objects, when its first visit (see objects_visited) completed, in s
/// since the start; nullopt if it was never visited.
std::vector<std::optional<double>> object_visit_times(const Trace& trace, double dwell_s);
/// summary.json's "visits": {object: time_s or null}.
Json visits_json(const Trace& trace, double dwell_s);

/// One experiment goal (the experiment file's `goals:`): metric <= value (kMax) or >= (kMin).
using GoalBound = config::GoalBound;
using Goal = config::GoalConfig;

struct GoalResult {
  Goal goal;
  std::optional<double> value;  ///< The metric's value, if the run has it.
  bool passed = false;
  std::string reason;  ///< Why it failed ("" when it passed).
};

/// A goal on an absent metric fails, with the metric's absent reason.
std::vector<GoalResult> evaluate_goals(const RunMetrics& metrics, std::span<const Goal> goals);
bool all_passed(std::span<const GoalResult> results);

/// summary.json's "metrics": {name: value} for the metrics present, in kMetricNames order.
Json metrics_json(const RunMetrics& metrics);
/// summary.json's "goals": {metric: {"max" or "min": bound, "value": value or null, "passed":
/// bool[, "reason": text]}}; two goals on one metric share its object (both bounds, passed when
/// both pass).
Json goals_json(std::span<const GoalResult> results);
/// summary.json's "final_joints": {joint: {"command_rad", "believed_rad", "true_rad"}} from the
/// last row (null where a value is missing); empty object for an empty trace.
Json final_joints_json(const Trace& trace);

}  // namespace cambio::app
