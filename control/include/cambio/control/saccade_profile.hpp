#pragma once

#include <span>
#include <vector>

namespace cambio::control {

/// A time-optimal synchronised point-to-point motion of several joints: every joint starts and
/// stops together, within its own velocity and acceleration limits; the slowest joint sets the
/// duration (the saccade of the paper's experiment 3, at the joints' limits).
///
/// Per joint, distance d, limits v, a: alone its fastest motion is a triangle of duration
/// 2 sqrt(d / a) when d <= v^2 / a (it never reaches v), else a trapezoid of duration
/// d / v + v / a. T is the largest of these. Every joint then accelerates at its own a to a
/// cruise speed c, cruises and brakes at a, taking exactly T: d = c (T - c / a), so
/// c = (a T - sqrt(a^2 T^2 - 4 a d)) / 2, the smaller root (a longer T gives a lower c, so
/// c <= v; the slowest joint gets its own optimum back).
///
/// plan() and sample() neither allocate nor throw (real-time safe); the constructor allocates.
/// Not thread-safe.
class SaccadeProfile {
 public:
  explicit SaccadeProfile(int joint_count);

  /// Plans from q0 to q1 (rad) with per-joint limits (> 0; a joint that does not move needs
  /// none). Returns the duration (s), 0 when nothing moves. For a span of the wrong size or a
  /// non-positive or non-finite limit of a moving joint, returns NaN and keeps the last plan.
  double plan(std::span<const double> q0, std::span<const double> q1,
              std::span<const double> max_velocity_rad_s,
              std::span<const double> max_acceleration_rad_s2) noexcept;

  /// Positions and velocities at t_s since the start: q0 before 0, q1 after duration_s().
  /// Spans of the wrong size are left untouched; qdot_rad_s may be empty.
  void sample(double t_s, std::span<double> q_rad, std::span<double> qdot_rad_s) const noexcept;

  double duration_s() const { return duration_s_; }
  int joint_count() const { return static_cast<int>(joints_.size()); }

 private:
  struct Joint {
    double q0_rad = 0.0;
    double distance_rad = 0.0;  ///< |q1 - q0|.
    double sign = 1.0;          ///< Direction of motion.
    double acceleration_rad_s2 = 0.0;
    double cruise_rad_s = 0.0;
  };
  std::vector<Joint> joints_;
  std::vector<Joint> scratch_;  ///< plan() builds here and swaps in only when valid.
  double duration_s_ = 0.0;
};

}  // namespace cambio::control
