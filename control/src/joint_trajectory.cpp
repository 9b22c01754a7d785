#include "cambio/control/joint_trajectory.hpp"

#include <algorithm>
#include <cmath>
#include <sstream>

namespace cambio::control {
namespace {

std::size_t at(int i) {
  return static_cast<std::size_t>(i);
}

/// One end of a segment for one joint.
struct Knot {
  double t_s = 0.0;
  double q_rad = 0.0;
  double v_rad_s = 0.0;
};

/// Knot k of joint j: k = -1 is the start (time 0, at rest); a first point at time 0 is the start.
Knot knot(const JointTrajectory& trajectory, std::span<const double> start_rad, int j,
          int k) noexcept {
  if (k < 0 || (k == 0 && trajectory.time_from_start_s[0] <= 0.0)) {
    return {0.0, start_rad[at(j)], 0.0};
  }
  const std::size_t p = at(k);
  return {trajectory.time_from_start_s[p], trajectory.positions_rad[p][at(j)],
          trajectory.has_velocities ? trajectory.velocities_rad_s[p][at(j)] : 0.0};
}

/// q(s) = ((a s + b) s + c) s + d for s in [0, 1] over a segment of h seconds: linear between
/// positions, or the cubic Hermite spline through positions and velocities.
struct Segment {
  double a = 0.0, b = 0.0, c = 0.0, d = 0.0, h_s = 0.0;

  Segment(const Knot& k0, const Knot& k1, bool cubic) noexcept : h_s(k1.t_s - k0.t_s) {
    d = k0.q_rad;
    if (!cubic) {
      c = k1.q_rad - k0.q_rad;
      return;
    }
    const double m0 = h_s * k0.v_rad_s;
    const double m1 = h_s * k1.v_rad_s;
    c = m0;
    b = -3.0 * k0.q_rad - 2.0 * m0 + 3.0 * k1.q_rad - m1;
    a = 2.0 * k0.q_rad + m0 - 2.0 * k1.q_rad + m1;
  }
  double position(double s) const noexcept { return ((a * s + b) * s + c) * s + d; }
  double velocity(double s) const noexcept { return ((3.0 * a * s + 2.0 * b) * s + c) / h_s; }
};

std::string text(double value) {
  std::ostringstream out;
  out.precision(4);
  out << value;
  return out.str();
}

std::string point_name(int k, const JointTrajectory& trajectory) {
  return "point " + std::to_string(k) + " (" + text(trajectory.time_from_start_s[at(k)]) + " s)";
}

/// The segment from knot k - 1 to knot k of joint j within its position and velocity limits.
std::string check_segment(const JointTrajectory& trajectory, std::span<const double> start_rad,
                          int j, int k, const hal::JointLimits& limits, const std::string& name) {
  const Knot k0 = knot(trajectory, start_rad, j, k - 1);
  const Knot k1 = knot(trajectory, start_rad, j, k);
  if (k1.t_s - k0.t_s <= 0.0) return {};  // The first point at time 0: no motion.
  const Segment segment(k0, k1, trajectory.has_velocities);
  const std::string where = "joint " + name + ": from " +
                            (k == 0 ? "where it is" : point_name(k - 1, trajectory)) + " to " +
                            point_name(k, trajectory);
  // Extremes of position where the velocity is zero, of velocity at the ends or its vertex.
  std::array<double, 3> candidates{0.0, 1.0, 0.5};
  int count = 2;
  double peak_velocity = std::max(std::abs(segment.velocity(0.0)), std::abs(segment.velocity(1.0)));
  if (segment.a != 0.0) {
    const double vertex = -segment.b / (3.0 * segment.a);
    if (vertex > 0.0 && vertex < 1.0) {
      peak_velocity = std::max(peak_velocity, std::abs(segment.velocity(vertex)));
    }
    const double qa = 3.0 * segment.a, qb = 2.0 * segment.b, qc = segment.c;
    const double discriminant = qb * qb - 4.0 * qa * qc;
    if (discriminant >= 0.0) {
      const double root = std::sqrt(discriminant);
      candidates[0] = (-qb - root) / (2.0 * qa);
      candidates[1] = (-qb + root) / (2.0 * qa);
      count = 2;
    }
  } else if (segment.b != 0.0) {
    candidates[0] = -segment.c / (2.0 * segment.b);
    count = 1;
  }
  constexpr double kSlack = 1e-9;
  for (int i = 0; i < count; ++i) {
    const double s = candidates[at(i)];
    if (!(s > 0.0 && s < 1.0)) continue;
    const double q = segment.position(s);
    if (q < limits.min_position_rad - kSlack || q > limits.max_position_rad + kSlack) {
      return where + ": the spline overshoots to " + text(q) + " rad, beyond its limits [" +
             text(limits.min_position_rad) + ", " + text(limits.max_position_rad) + "] rad";
    }
  }
  if (peak_velocity > limits.max_velocity_rad_s * (1.0 + kSlack)) {
    return where + ": " + text(peak_velocity) + " rad/s, above its " +
           text(limits.max_velocity_rad_s) + " rad/s limit";
  }
  return {};
}

}  // namespace

void sample_joint_trajectory(const JointTrajectory& trajectory, std::span<const double> start_rad,
                             double t_s, std::span<double> out_rad) noexcept {
  const int n = trajectory.point_count;
  const auto times = std::span(trajectory.time_from_start_s).first(at(std::max(n, 0)));
  // The first knot after t_s: the segment ends there (n: past the end, hold the last point).
  const int k = static_cast<int>(std::upper_bound(times.begin(), times.end(), t_s) - times.begin());
  for (int j = 0; j < trajectory.joint_count; ++j) {
    if (k >= n) {
      out_rad[at(j)] = n > 0 ? knot(trajectory, start_rad, j, n - 1).q_rad : start_rad[at(j)];
      continue;
    }
    const Knot k0 = knot(trajectory, start_rad, j, k - 1);
    const Knot k1 = knot(trajectory, start_rad, j, k);
    const Segment segment(k0, k1, trajectory.has_velocities);
    const double s = segment.h_s > 0.0 ? std::clamp((t_s - k0.t_s) / segment.h_s, 0.0, 1.0) : 1.0;
    out_rad[at(j)] = segment.position(s);
  }
}

std::string check_joint_trajectory(const JointTrajectory& trajectory,
                                   std::span<const hal::JointLimits> limits,
                                   std::span<const double> measured_rad,
                                   std::span<const std::string> names) {
  const int joints = trajectory.joint_count;
  const int points = trajectory.point_count;
  if (joints < 1 || joints > JointTrajectory::kMaxJoints) {
    return std::to_string(joints) + " joints: a trajectory moves 1 to " +
           std::to_string(JointTrajectory::kMaxJoints);
  }
  if (points < 1 || points > JointTrajectory::kMaxPoints) {
    return std::to_string(points) + " points: a trajectory has 1 to " +
           std::to_string(JointTrajectory::kMaxPoints);
  }
  if (limits.size() != at(joints) || measured_rad.size() != at(joints) ||
      names.size() != at(joints)) {
    return "the joints' limits, measured positions and names do not match the trajectory's joints";
  }
  for (int k = 0; k < points; ++k) {
    const double t = trajectory.time_from_start_s[at(k)];
    if (!std::isfinite(t) || t < 0.0 || t > kMaxTrajectoryDuration_s) {
      return point_name(k, trajectory) + ": a time from start must be within [0, " +
             text(kMaxTrajectoryDuration_s) + "] s";
    }
    if (k > 0 && !(t > trajectory.time_from_start_s[at(k - 1)])) {
      return point_name(k, trajectory) + ": not after " + point_name(k - 1, trajectory) +
             " (times must increase)";
    }
    for (int j = 0; j < joints; ++j) {
      const double q = trajectory.positions_rad[at(k)][at(j)];
      const hal::JointLimits& limit = limits[at(j)];
      const std::string where = "joint " + names[at(j)] + ", " + point_name(k, trajectory);
      if (!std::isfinite(q) || q < limit.min_position_rad || q > limit.max_position_rad) {
        return where + ": position " + text(q) + " rad is not within its limits [" +
               text(limit.min_position_rad) + ", " + text(limit.max_position_rad) + "] rad";
      }
      const double v = trajectory.velocities_rad_s[at(k)][at(j)];
      if (trajectory.has_velocities && !(std::abs(v) <= limit.max_velocity_rad_s)) {
        return where + ": velocity " + text(v) + " rad/s is beyond its " +
               text(limit.max_velocity_rad_s) + " rad/s limit";
      }
    }
  }
  for (int j = 0; j < joints; ++j) {
    const double gap = std::abs(trajectory.positions_rad[0][at(j)] - measured_rad[at(j)]);
    if (trajectory.time_from_start_s[0] <= 0.0 && gap > kTrajectoryStartTolerance_rad) {
      return "joint " + names[at(j)] + ": " + point_name(0, trajectory) + " is " + text(gap) +
             " rad from where the joint is (a jump; more than " +
             text(kTrajectoryStartTolerance_rad) + " rad)";
    }
    for (int k = 0; k < points; ++k) {
      std::string why = check_segment(trajectory, measured_rad, j, k, limits[at(j)], names[at(j)]);
      if (!why.empty()) return why;
    }
  }
  return {};
}

}  // namespace cambio::control
