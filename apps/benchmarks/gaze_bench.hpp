#pragma once

// `cambio gaze-bench`'s measurement: the gaze behaviour on scenes nobody shipped. N runs per task
// are generated from the seed (gaze_scene_generator.hpp), run J at a time in child processes and
// scored against the simulator's ground truth (gaze_bench_runs.hpp), and summarised per task
// with the disparity confidence's calibration (gaze_bench_summary.hpp).

#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "gaze_scene_generator.hpp"

namespace cambio::app {

struct GazeBenchOptions {
  int scenes = 20;  ///< Generated runs per task.
  std::uint64_t seed = 1;
  int jobs = 1;  ///< Runs at once, each in a process of its own.
  std::vector<GazeBenchTask> tasks;
  std::string rig_path;         ///< Written into every run's experiment as given.
  std::string perception_path;  ///< Likewise.
  /// An existing directory that receives each failed run's experiment and scene files.
  std::optional<std::filesystem::path> keep_failures;
  bool json = false;  ///< One JSON object (per task, per run, the calibration) instead of a table.
};

/// Generates, runs and scores the runs, showing progress on stderr, and prints the summary.
/// Returns the exit status: 128 + the signal when a stop signal cut the bench short (the runs
/// that finished are summarised). Throws std::runtime_error when the scratch folder, a pipe or a
/// process cannot be made.
int run_gaze_bench(const GazeBenchOptions& options);

}  // namespace cambio::app
