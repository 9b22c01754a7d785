#pragma once

// What an experiment run did over time, for scoring (run_metrics.hpp), trace.csv, plots
// (run_plots.hpp) and key frames: the TraceRecorder samples the control side's channels and the
// simulator's ground truth at the control rate.

#include <string>

#include "trace.hpp"
#include "trace_recorder.hpp"

namespace cambio::app {

class OutputDirectory;

/// The reach phase's name as trace.csv and summary.json write it.
const char* reach_phase_name(control::ReachPhase phase);

/// trace.csv: a header row whose names carry their units (time_s, <joint>_command_rad, ...,
/// disparity_px, ...), one row per sample; NaN is written as "nan", booleans as 0/1, the gaze
/// action as hold/fixate/saccade/pursue (empty without a gaze loop).
std::string trace_csv(const Trace& trace);

/// The file name a key frame is staged under: key_<time, ms>ms_<camera>.png.
std::string key_frame_file_name(const KeyFrame& frame);

/// Stages trace.csv in `out`. Throws OutputError on a failed write.
void stage_trace(OutputDirectory& out, const Trace& trace);

/// The gaze action's name as trace.csv and summary.json write it.
const char* gaze_action_name(control::GazeAction action);

}  // namespace cambio::app
