#pragma once

// Scenes nobody tuned on, for `cambio gaze-bench`: from a seed, random targets (depth, azimuth,
// elevation, shape, size, procedural texture), backdrops and distractors, each with the gaze
// task to run on it and the geometric truth it is scored against. A generated run is plain
// experiment and scene YAML (loaded by the same loaders as a user's files), so any failure can be
// written out and replayed with `cambio run`.

#include <array>
#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

namespace cambio::app {

/// What a generated run asks of the gaze.
enum class GazeBenchTask : std::uint8_t {
  kVerge,         ///< Dominant eye on a textured target, the other parallel: verge.
  kSaccadeDepth,  ///< Verge on one object, saccade to another at a different depth, re-verge.
  kDistractors,   ///< kVerge with 1-3 objects crossing the view in front of or behind it.
  kPursuit,       ///< Follow a target moving across the view at 5-30 deg/s.
  kUntextured,    ///< kVerge on a plain target: may fail, must not verge on a wrong surface.
};
inline constexpr std::array<GazeBenchTask, 5> kGazeBenchTasks{
    GazeBenchTask::kVerge, GazeBenchTask::kSaccadeDepth, GazeBenchTask::kDistractors,
    GazeBenchTask::kPursuit, GazeBenchTask::kUntextured};
std::string_view task_name(GazeBenchTask task);

/// Where the head's eyes are at the rig's zero pose (world frame, x forward, y left, z up): the
/// dominant (left) eye's pan axis origin, from which targets are placed and the start pose aimed.
struct HeadGeometry {
  std::array<double, 3> left_eye_W_m{0.04, 0.06, 1.40};
  std::array<double, 3> right_eye_W_m{0.04, -0.06, 1.40};
};

/// One generated run: the files to load and the truth the generator put in them.
struct GeneratedGazeRun {
  GazeBenchTask task = GazeBenchTask::kVerge;
  int index = 0;           ///< Within its task.
  std::uint64_t seed = 0;  ///< The run's own seed (scene textures and the sim's noise).
  std::string name;        ///< e.g. "verge_017"; the files' stem.
  std::string scene_yaml;
  /// Refers to the rig by `rig_path` and to the scene as `<name>.scene.yaml` beside it.
  std::string experiment_yaml;
  // Truth, for the report (the scoring itself reads the simulator's ground truth).
  std::string target_object;
  double target_depth_m = 0.0;      ///< From the dominant eye to the target's centre.
  double target_azimuth_deg = 0.0;  ///< Positive left.
  double target_elevation_deg = 0.0;
  std::string target_shape;          ///< sphere, box or cylinder.
  std::string target_texture;        ///< noise, checker, dots, stripes, or none (untextured).
  double second_depth_m = 0.0;       ///< kSaccadeDepth: the saccade's target.
  double pursuit_speed_deg_s = 0.0;  ///< kPursuit.
  double saccade_at_s = 0.0;         ///< kSaccadeDepth: when the saccade is commanded.
  double pursue_at_s = 0.0;          ///< kPursuit: when pursuit starts.
  int distractors = 0;
};

/// Generates run `index` of `task` from `bench_seed` (the same arguments, the same run, on any
/// machine: a std::mt19937_64 seeded from the three, no other source of randomness).
/// `rig_path` is written into the experiment as given; `perception_path` likewise (may be empty).
GeneratedGazeRun generate_gaze_run(GazeBenchTask task, int index, std::uint64_t bench_seed,
                                   const HeadGeometry& head, const std::string& rig_path,
                                   const std::string& perception_path);

}  // namespace cambio::app
