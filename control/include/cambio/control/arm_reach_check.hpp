#pragma once

#include <array>
#include <numbers>
#include <string_view>

#include <Eigen/Core>

#include "cambio/control/arm_chain.hpp"

namespace cambio::control {

/// Which hand pitches (ArmChain: downward from level) a reach may end with.
struct HandPitchRange {
  double preferred_rad = 0.0;  ///< Tried first: a level hand meets a front face fingers first.
  double max_deviation_rad = 60.0 * std::numbers::pi / 180.0;  ///< Then outward to this, ...
  double step_rad = 2.0 * std::numbers::pi / 180.0;            ///< ... in these steps.
};

/// What check_reach() found: joints that put the fingertips' midpoint on the target within every
/// joint's limits, or why there are none.
struct ReachCheck {
  bool reachable = false;
  /// Yaw, shoulder pitch, elbow, wrist (rad), and the hand's pitch they give.
  std::array<double, 4> q_rad{};
  double hand_pitch_rad = 0.0;
  /// Why not (NUL-terminated): "out of reach: ..." or "beyond a joint limit: ...".
  std::array<char, 160> message{};

  std::string_view why() const { return std::string_view(message.data()); }
};

/// The reach check at command time: closed-form inverse kinematics of `arm` (ArmChain's shape)
/// for the fingertips' midpoint at `target_W` (base frame, m) with the gripper at `opening_rad`,
/// trying hand pitches from `pitches.preferred_rad` outward. Refuses, saying why:
///  - "out of reach": the target is further from the shoulder than the arm reaches (both
///    distances given), or no hand pitch in range places the wrist where the upper arm and
///    forearm can take it (too close to the shoulder);
///  - "beyond a joint limit": the solution nearest the preferred pitch needs a joint beyond its
///    limits (the joint, the angle and the limits given).
/// Real-time safe: no allocation (the message is formatted into a fixed buffer).
ReachCheck check_reach(const ArmChain& arm, double opening_rad, const Eigen::Vector3d& target_W,
                       const HandPitchRange& pitches) noexcept;

/// The fingertips' midpoint for arm joints `q_rad` (yaw, pitch, elbow, wrist) at gripper
/// opening `opening_rad`, in the base frame: ArmChain's forward kinematics in closed form (the
/// oracle the tests hold the general Kinematics against, and check_reach's own check).
Eigen::Vector3d fingertips_W(const ArmChain& arm, double opening_rad,
                             const std::array<double, 4>& q_rad) noexcept;

}  // namespace cambio::control
