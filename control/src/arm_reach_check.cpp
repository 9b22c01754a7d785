#include "cambio/control/arm_reach_check.hpp"

#include <algorithm>
#include <cmath>
#include <cstdarg>
#include <cstdio>

namespace cambio::control {
namespace {

constexpr double kDegPerRad = 180.0 / std::numbers::pi;
constexpr double kTwoPi = 2.0 * std::numbers::pi;

// A printf-style function (not a template) so that the compiler checks every format against its
// arguments.
[[gnu::format(printf, 2, 3)]] void say(std::array<char, 160>& message, const char* format,
                                       ...) noexcept {
  std::va_list args;
  va_start(args, format);
  std::vsnprintf(message.data(), message.size(), format, args);
  va_end(args);
}

}  // namespace

Eigen::Vector3d fingertips_W(const ArmChain& arm, double opening_rad,
                             const std::array<double, 4>& q_rad) noexcept {
  const double a1 = q_rad[1];
  const double a2 = a1 + q_rad[2];
  const double a3 = a2 + q_rad[3];
  const double hand_m = arm.hand_m(opening_rad);
  // In the arm's plane: r outward, z up; pitch angles point below the horizontal.
  const double r =
      arm.upper_arm_m * std::cos(a1) + arm.forearm_m * std::cos(a2) + hand_m * std::cos(a3);
  const double z =
      -(arm.upper_arm_m * std::sin(a1) + arm.forearm_m * std::sin(a2) + hand_m * std::sin(a3));
  return arm.shoulder_W + Eigen::Vector3d(r * std::cos(q_rad[0]), r * std::sin(q_rad[0]), z);
}

ReachCheck check_reach(const ArmChain& arm, double opening_rad, const Eigen::Vector3d& target_W,
                       const HandPitchRange& pitches) noexcept {
  ReachCheck result;
  const Eigen::Vector3d d = target_W - arm.shoulder_W;
  const double distance_m = d.norm();
  const double hand_m = arm.hand_m(opening_rad);
  const double reach_m = arm.upper_arm_m + arm.forearm_m + hand_m;
  if (!target_W.allFinite()) {
    say(result.message, "out of reach: the target is not a finite point");
    return result;
  }
  if (distance_m > reach_m) {
    say(result.message,
        "out of reach: the target is %.3f m from %s's shoulder, the arm reaches %.3f m", distance_m,
        arm.group.c_str(), reach_m);
    return result;
  }
  const double r = std::hypot(d.x(), d.y());
  // Straight above or below the shoulder any yaw will do: keep the one nearest zero.
  const double yaw = r > 1e-9 ? std::atan2(d.y(), d.x()) : 0.0;
  const hal::JointLimits& yaw_limits = arm.limits[0];
  if (yaw < yaw_limits.min_position_rad || yaw > yaw_limits.max_position_rad) {
    say(result.message,
        "beyond a joint limit: %s would need %.1f deg, its limits are [%.1f, %.1f] deg",
        arm.names[0].c_str(), yaw * kDegPerRad, yaw_limits.min_position_rad * kDegPerRad,
        yaw_limits.max_position_rad * kDegPerRad);
    return result;
  }
  const double down = -d.z();  // Downward, as the pitch angles are measured.
  const double l1 = arm.upper_arm_m;
  const double l2 = arm.forearm_m;
  bool any_geometric = false;
  const int steps = static_cast<int>(pitches.max_deviation_rad / pitches.step_rad);
  for (int k = 0; k <= 2 * steps; ++k) {
    // preferred, +step, -step, +2 step, ...
    const int n = (k + 1) / 2;
    const double sign = k % 2 == 1 ? 1.0 : -1.0;
    const double phi = pitches.preferred_rad + sign * n * pitches.step_rad;
    const double wx = r - hand_m * std::cos(phi);
    const double wz = down - hand_m * std::sin(phi);
    const double c2 = (wx * wx + wz * wz - l1 * l1 - l2 * l2) / (2.0 * l1 * l2);
    if (c2 < -1.0 || c2 > 1.0) continue;
    // The elbow bends downward (q_elbow >= 0), the branch its limits allow on this arm.
    // Angles in (-pi, pi]: every limit lies within, and a difference of atan2s may not.
    const double q2 = std::acos(c2);
    const double q1 = std::remainder(
        std::atan2(wz, wx) - std::atan2(l2 * std::sin(q2), l1 + l2 * std::cos(q2)), kTwoPi);
    const double q3 = std::remainder(phi - q1 - q2, kTwoPi);
    const std::array<double, 4> q{yaw, q1, q2, q3};
    int beyond = -1;
    for (int j = 1; j < 4; ++j) {
      const hal::JointLimits& limits = arm.limits[static_cast<std::size_t>(j)];
      if (q[static_cast<std::size_t>(j)] < limits.min_position_rad ||
          q[static_cast<std::size_t>(j)] > limits.max_position_rad) {
        beyond = j;
        break;
      }
    }
    if (beyond < 0) {
      result.reachable = true;
      result.q_rad = q;
      result.hand_pitch_rad = phi;
      return result;
    }
    if (!any_geometric) {
      // The solution nearest the preferred pitch says which joint is in the way.
      const hal::JointLimits& limits = arm.limits[static_cast<std::size_t>(beyond)];
      say(result.message,
          "beyond a joint limit: %s would need %.1f deg (hand pitch %.0f deg), its limits are "
          "[%.1f, %.1f] deg",
          arm.names[static_cast<std::size_t>(beyond)].c_str(),
          q[static_cast<std::size_t>(beyond)] * kDegPerRad, phi * kDegPerRad,
          limits.min_position_rad * kDegPerRad, limits.max_position_rad * kDegPerRad);
    }
    any_geometric = true;
  }
  if (!any_geometric) {
    say(result.message,
        "out of reach: the target is %.3f m from %s's shoulder, too close for a hand pitch "
        "within %.0f deg of %.0f deg",
        distance_m, arm.group.c_str(), pitches.max_deviation_rad * kDegPerRad,
        pitches.preferred_rad * kDegPerRad);
  }
  return result;
}

}  // namespace cambio::control
