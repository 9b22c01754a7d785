#pragma once

// How `cambio gaze-bench` runs its generated runs: each in lockstep in a child process of its own
// (runs are independent, and a run's renderer and GL state stay in its process), scored there
// against the simulator's ground truth (gaze_bench_score.hpp) and sent to the parent as JSON.

#include <atomic>
#include <cstddef>
#include <filesystem>
#include <functional>
#include <vector>

#include "gaze_scene_generator.hpp"
#include "json_output.hpp"

namespace cambio::app {

/// Writes the run's experiment and scene files into `directory` and returns the experiment
/// file's path. Throws std::runtime_error when a file cannot be written.
std::filesystem::path write_gaze_run_files(const GeneratedGazeRun& run,
                                           const std::filesystem::path& directory);

/// Runs every run in a child process, `jobs` at a time, its files written into `scratch`; calls
/// `done(run index, json)` as each ends: its score (the truth it was generated with and the
/// figures gaze_bench_score.hpp defines), or an object with "error" when it failed or its
/// process died. Starts no more runs once `stop` is set. Throws std::runtime_error when a pipe,
/// fork or poll fails.
void run_in_child_processes(const std::vector<GeneratedGazeRun>& runs, int jobs,
                            const std::filesystem::path& scratch, const std::atomic<bool>& stop,
                            const std::function<void(std::size_t, Json)>& done);

}  // namespace cambio::app
