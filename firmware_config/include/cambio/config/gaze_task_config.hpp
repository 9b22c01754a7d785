#pragma once

#include <array>
#include <cstdint>
#include <numbers>
#include <optional>
#include <string>
#include <vector>

#include "cambio/config/arm_task_config.hpp"

#include "cambio/hal/eye.hpp"

namespace cambio::config {

// The gaze task of an experiment file (`task: gaze`, `gaze:` and `commands:`). These are the
// config's own types: firmware_config does not depend on control/, and apps/ maps them onto
// control::GazeCommand and the gaze loop's parameters. The member initialisers are the defaults
// for keys a file leaves out, and the only copy of them.

/// The vergence of the eye that is not dominant (`gaze.vergence`), by control::VergenceController.
struct GazeVergenceConfig {
  bool enabled = true;
  double gain = 0.5;            ///< Fraction of the angular error corrected per measurement.
  double min_confidence = 0.3;  ///< Ignore measurements below this.
  double max_step_rad = 0.05;   ///< Largest correction per measurement.
};

/// `gaze.saccade`.
struct GazeSaccadeConfig {
  /// For a saccade to a 3-D target (an object or a point), set the verging eye from the target's
  /// depth during the saccade, then refine it by vision; false: move it conjugately and re-verge
  /// once the dominant eye stops (the paper's behaviour, slow across depths).
  bool predictive_vergence = true;
};

/// `gaze.pursuit` (keys `position_gain`, `velocity_gain`).
struct GazePursuitConfig {
  double position_gain_per_s = 4.0;  ///< On the gaze's angular error to the target; > 0.
  /// The fraction of the SSM's motion estimate fed forward, in [0, 2]: 1 as measured.
  double velocity_gain = 1.0;
};

/// `gaze:`: the fixation servo and what rides on it.
struct GazeTaskConfig {
  hal::Eye dominant_eye = hal::Eye::kLeft;  ///< The other eye verges.
  double fixation_gain_per_s = 4.0;         ///< The IBVS gain (ViSP's lambda).
  /// Eye pan (either eye) beyond which the neck takes over and the eyes come back: the paper's
  /// 30 degrees. In (0, pi/2].
  double neck_rule_rad = 30.0 * std::numbers::pi / 180.0;
  double default_depth_m = 1.0;  ///< The depth assumed for a pixel or angle target.
  GazeVergenceConfig vergence;
  GazeSaccadeConfig saccade;
  GazePursuitConfig pursuit;
};

/// Mirrors control::GazeAction (the same enumerators, in the same order).
enum class GazeAction : std::uint8_t { kHold, kFixate, kSaccade, kPursue };

/// Mirrors control::GazeTargetKind. A target given as a scene object is a kPoint.
enum class GazeTargetKind : std::uint8_t { kNone, kPoint, kPixel, kAngles };

/// A command's target: exactly one of `object`, `point_m`, `pixel`, `angles_deg` (or
/// `angles_rad`) in the file.
struct GazeTargetConfig {
  GazeTargetKind kind = GazeTargetKind::kNone;
  /// The scene object the file named (`object: NAME`), empty otherwise. point_W_m then holds its
  /// centre at the start of the run, from the scene (with the experiment's `scene.` overrides).
  std::string object;
  std::array<double, 3> point_W_m{};  ///< kPoint: base (world) frame, x forward, y left, z up.
  std::array<double, 2> pixel_px{};   ///< kPixel: (u right, v down) in the dominant eye's image.
  /// kAngles: (pan positive to the robot's left, tilt positive looking down) from the current
  /// gaze; `angles_deg` in the file.
  std::array<double, 2> angles_rad{};
};

/// One entry of `commands:`, sent at sim time at_s: to the gaze loop, or to the arms when `arm`
/// is set (the gaze fields are then unused).
struct GazeCommandConfig {
  double at_s = 0.0;  ///< In [0, duration_s]; not less than the entry before.
  GazeAction action = GazeAction::kHold;
  GazeTargetConfig target;  ///< kNone for hold and pursue.
  bool verge = true;        ///< The other eye verges on what the dominant eye fixates.
  std::optional<ArmCommandConfig> arm;
};

}  // namespace cambio::config
