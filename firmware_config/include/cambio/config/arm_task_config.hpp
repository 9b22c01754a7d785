#pragma once

#include <array>
#include <cstdint>

namespace cambio::config {

// The arms in an experiment file (`arm:` and the arm entries of `commands:`). The config's own
// types, as gaze_task_config.hpp: apps/ maps them onto control::ArmReachParams and
// control::ArmCommand. The member initialisers are the defaults for keys a file leaves out, and
// the only copy of them.

/// `arm:`: the arm loop's reach (control::ArmReachLoop), used when the rig has arms.
struct ArmTaskConfig {
  double gain_per_s = 3.0;             ///< `gain`: fingertip speed per metre of error (1/s).
  double max_speed_m_s = 0.4;          ///< Cap on the fingertips' speed.
  double max_acceleration_m_s2 = 2.0;  ///< The cap's ramp from the command.
  /// How far past the target the servo aims (a guarded move: the touch stops it first).
  double probe_depth_m = 0.03;
  /// How far in front of the target the fingertips go first, to meet it head-on.
  double approach_m = 0.08;
  double arrive_tolerance_m = 0.002;  ///< At the aim within this without a touch: arrived.
  double posture_gain_per_s = 2.0;    ///< The joints toward the reach check's solution.
  double gripper_speed_rad_s = 1.5;   ///< Opening and closing.
};

/// Mirrors control::ArmAction (the actions a script may send).
enum class ArmActionConfig : std::uint8_t { kReach, kGrasp, kRelease };

/// Mirrors control::ArmSide; for grasp and release `both` is kNearest.
enum class ArmSideConfig : std::uint8_t { kNearest, kLeft, kRight };

/// An arm entry of `commands:`: `reach: fixation` or `reach: [x, y, z]` (with `arm: nearest |
/// left | right`), `grasp: both | left | right`, `release: both | left | right`.
struct ArmCommandConfig {
  ArmActionConfig action = ArmActionConfig::kReach;
  ArmSideConfig arm = ArmSideConfig::kNearest;
  bool to_fixation = true;            ///< reach: what the head fixates (its stereo estimate).
  std::array<double, 3> point_W_m{};  ///< reach: the point otherwise (base frame, m).
};

}  // namespace cambio::config
