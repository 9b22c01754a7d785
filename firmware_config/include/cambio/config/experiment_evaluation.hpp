#pragma once

#include <array>
#include <cstdint>
#include <numbers>
#include <string>
#include <string_view>
#include <vector>

namespace cambio::config {

// How a run is judged: `evaluation:` (what the metrics measure against) and `goals:` (which
// metrics must reach what for the run to pass; `cambio run` exits 1 when one does not).

/// The metrics a run reports in summary.json (units in the name), and so the names `goals:` may
/// use. apps/ computes them; a name added there is added here.
inline constexpr std::array<std::string_view, 18> kExperimentMetricNames{
    "final_disparity_px",
    "true_gaze_error_deg",
    "settle_time_s",
    "saccade_duration_s",
    "max_vergence_error_during_saccade_deg",
    "reverge_time_s",
    "pursuit_rms_error_deg",
    "max_believed_vs_true_joint_error_rad",
    "final_believed_vs_true_fixation_error_m",
    "max_believed_vs_true_fixation_error_m",
    "final_max_abs_eye_pan_deg",
    "max_verging_gaze_error_visible_deg",
    "target_occluded_s",
    "objects_visited",
    "all_objects_visited_s",
    "time_to_touch_s",
    "touch_position_error_m",
    "estimated_target_error_m",
};

/// When the gaze counts as settled (settle_time_s, reverge_time_s): both bounds hold.
struct SettleConfig {
  double disparity_px = 0.5;                               ///< |disparity|, level-0 px; > 0.
  double gaze_error_rad = 0.1 * std::numbers::pi / 180.0;  ///< True gaze error; `_deg` in files.
};

/// `evaluation:`; every key is optional.
struct EvaluationConfig {
  /// The scene object the gaze (and a reach) is judged against; empty when the file names none.
  /// Checked
  /// against the scene's objects when the experiment has a scene.
  std::string target_object;
  std::vector<double> key_frames_s;  ///< Sim times of the key frames, each in [0, duration_s].
  SettleConfig settle;
  /// How long pursuit has to catch up after it starts before pursuit_rms_error_deg counts.
  double pursuit_catch_up_s = 0.5;
  /// The scene objects a scan should visit (objects_visited, all_objects_visited_s); each
  /// checked against the scene.
  std::vector<std::string> visit_objects;
  /// A visit: the dominant eye's true optical axis meets the object for at least this long
  /// while the gaze loop reports no saccade (> 0).
  double visit_dwell_s = 0.2;
};

enum class GoalBound : std::uint8_t {
  kMax,  ///< Passes when the metric is at most `value`.
  kMin,  ///< Passes when the metric is at least `value`.
};

/// One entry of `goals:` (`settle_time_s: {max: 1.0}`).
struct GoalConfig {
  std::string metric;  ///< One of kExperimentMetricNames.
  GoalBound bound = GoalBound::kMax;
  double value = 0.0;
};

}  // namespace cambio::config
