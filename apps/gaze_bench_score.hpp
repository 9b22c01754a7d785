#pragma once

// How `cambio gaze-bench` scores one generated run, from its trace (the simulator's ground truth
// at the control rate), never from the program's own estimates. Definitions, a row being one
// control cycle and "after t" the rows from t to the end:
//  verged_at_s        Of the verging eye: the first time after which every row not marked
//                     target_occluded has a true verging gaze error <= verged_deg (held to the
//                     end); measured from `from_s` (the start, or the dominant eye's stop after
//                     a saccade). Absent if the last row is not verged.
//  first_verged_s     The first row at or after from_s with error <= verged_deg.
//  final_error_deg    The last row's true verging gaze error (dominant: for pursuit).
//  off_target_s       After first_verged_s, the time of rows not target_occluded whose verging
//                     error exceeds off_target_deg: verged on another surface, or on the way.
//  longest_off_target_s  The longest unbroken stretch of such rows (occluded rows neither add to
//                     a stretch nor end it): what kDistractors' goal bounds ("never more than
//                     max_off_target_s verged elsewhere"), to within a hundredth of a row.
//  occluded_s         The time of rows marked target_occluded.
//  pursuit_rms_deg    RMS of the dominant eye's true gaze error from pursue_at_s + catch-up.
//  saccade_stop_s     The first row after saccade_at_s at which the gaze loop's saccade is over.
// Each measurement the SSM made (a row whose measured disparity differs from the row before)
// is also compared with the true disparity for the confidence calibration: right when within
// calibration_tolerance_px.

#include <optional>
#include <vector>

#include "gaze_scene_generator.hpp"
#include "run_trace.hpp"

namespace cambio::app {

struct GazeScoreSettings {
  double verged_deg = 0.2;
  double off_target_deg = 0.5;
  double pursuit_catch_up_s = 0.6;
  double calibration_tolerance_px = 2.0;
  double verge_within_s = 1.0;        ///< kVerge, kDistractors, kUntextured.
  double reverge_within_s = 0.3;      ///< kSaccadeDepth, from the dominant eye's stop.
  double max_off_target_s = 0.1;      ///< kDistractors.
  double pursuit_rms_slow_deg = 0.5;  ///< Up to pursuit_fast_above_deg_s.
  double pursuit_rms_fast_deg = 1.0;
  double pursuit_fast_above_deg_s = 20.0;
};

/// One measurement for the calibration table.
struct CalibrationSample {
  double confidence = 0.0;
  bool right = false;
};

struct GazeRunScore {
  bool success = false;
  std::string failure;  ///< Why not, in words ("" on success).
  std::optional<double> verged_at_s;
  std::optional<double> first_verged_s;
  std::optional<double> final_error_deg;
  std::optional<double> worst_error_deg;  ///< Verging error, after first_verged_s.
  double off_target_s = 0.0;
  double longest_off_target_s = 0.0;
  double occluded_s = 0.0;
  std::optional<double> pursuit_rms_deg;
  std::optional<double> saccade_stop_s;
  std::vector<CalibrationSample> calibration;
};

GazeRunScore score_gaze_run(const GeneratedGazeRun& run, const Trace& trace,
                            const GazeScoreSettings& settings = {});

}  // namespace cambio::app
