#include "cambio/control/saccade_profile.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

namespace cambio::control {

SaccadeProfile::SaccadeProfile(int joint_count) {
  if (joint_count < 0) throw std::invalid_argument("saccade profile: negative joint count");
  joints_.resize(static_cast<std::size_t>(joint_count));
  scratch_.resize(static_cast<std::size_t>(joint_count));
}

double SaccadeProfile::plan(std::span<const double> q0, std::span<const double> q1,
                            std::span<const double> max_velocity_rad_s,
                            std::span<const double> max_acceleration_rad_s2) noexcept {
  constexpr double kInvalid = std::numeric_limits<double>::quiet_NaN();
  const std::size_t n = joints_.size();
  if (q0.size() != n || q1.size() != n || max_velocity_rad_s.size() != n ||
      max_acceleration_rad_s2.size() != n) {
    return kInvalid;
  }
  double duration_s = 0.0;
  for (std::size_t i = 0; i < n; ++i) {
    if (!std::isfinite(q0[i]) || !std::isfinite(q1[i])) return kInvalid;
    Joint& joint = scratch_[i];
    joint = Joint{};
    joint.q0_rad = q0[i];
    joint.distance_rad = std::abs(q1[i] - q0[i]);
    joint.sign = q1[i] >= q0[i] ? 1.0 : -1.0;
    if (joint.distance_rad == 0.0) continue;
    const double v = max_velocity_rad_s[i];
    const double a = max_acceleration_rad_s2[i];
    if (!(v > 0.0) || !(a > 0.0) || !std::isfinite(v) || !std::isfinite(a)) return kInvalid;
    joint.acceleration_rad_s2 = a;
    const double d = joint.distance_rad;
    const double alone_s = d <= v * v / a ? 2.0 * std::sqrt(d / a) : d / v + v / a;
    duration_s = std::max(duration_s, alone_s);
  }
  for (Joint& joint : scratch_) {
    if (joint.distance_rad == 0.0) continue;
    const double a = joint.acceleration_rad_s2;
    const double aT = a * duration_s;
    // Rounding may make the slowest triangle's discriminant slightly negative: it is 0.
    const double discriminant = std::max(0.0, aT * aT - 4.0 * a * joint.distance_rad);
    joint.cruise_rad_s = 0.5 * (aT - std::sqrt(discriminant));
  }
  joints_.swap(scratch_);
  duration_s_ = duration_s;
  return duration_s;
}

void SaccadeProfile::sample(double t_s, std::span<double> q_rad,
                            std::span<double> qdot_rad_s) const noexcept {
  const std::size_t n = joints_.size();
  if (q_rad.size() != n || (!qdot_rad_s.empty() && qdot_rad_s.size() != n)) return;
  const double T = duration_s_;
  const double t = std::clamp(t_s, 0.0, T);
  for (std::size_t i = 0; i < n; ++i) {
    const Joint& joint = joints_[i];
    double s = 0.0;  // Distance travelled.
    double s_dot = 0.0;
    if (joint.distance_rad > 0.0) {
      const double a = joint.acceleration_rad_s2;
      const double c = joint.cruise_rad_s;
      const double ramp_s = c / a;
      if (t >= T) {
        s = joint.distance_rad;
      } else if (t < ramp_s) {
        s = 0.5 * a * t * t;
        s_dot = a * t;
      } else if (t <= T - ramp_s) {
        s = 0.5 * a * ramp_s * ramp_s + c * (t - ramp_s);
        s_dot = c;
      } else {
        const double left_s = T - t;
        s = joint.distance_rad - 0.5 * a * left_s * left_s;
        s_dot = a * left_s;
      }
    }
    q_rad[i] = joint.q0_rad + joint.sign * s;
    if (!qdot_rad_s.empty()) qdot_rad_s[i] = joint.sign * s_dot;
  }
}

}  // namespace cambio::control
