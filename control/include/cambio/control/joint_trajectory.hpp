#pragma once

#include <array>
#include <cstdint>
#include <span>
#include <string>

#include "cambio/hal/joint_group.hpp"

namespace cambio::control {

/// A time-parameterised motion of a few joints (ROS's trajectory_msgs/JointTrajectory, without
/// names: the joints are rig indices). Fixed capacity and trivially copyable: it travels through
/// SeqlockChannel to a loop that must not allocate.
///
/// Interpolation as ROS's joint_trajectory_controller does it: positions only, linear between
/// points (continuous positions, velocity steps at the points); positions and velocities, a cubic
/// Hermite spline through both. The motion starts at rest from where the joints are commanded
/// when a loop takes it; a first point at time 0 is that start (its positions are replaced by the
/// commanded ones, so nothing jumps). After the last point the joints hold it.
struct JointTrajectory {
  static constexpr int kMaxJoints = 8;
  static constexpr int kMaxPoints = 128;

  std::uint64_t sequence = 0;  ///< A new sequence number is a new trajectory.
  int joint_count = 0;
  int point_count = 0;
  bool has_velocities = false;
  std::array<int, kMaxJoints> joint_rig_index{};
  std::array<double, kMaxPoints> time_from_start_s{};
  std::array<std::array<double, kMaxJoints>, kMaxPoints> positions_rad{};
  std::array<std::array<double, kMaxJoints>, kMaxPoints> velocities_rad_s{};

  double duration_s() const noexcept {
    return point_count > 0 ? time_from_start_s[static_cast<std::size_t>(point_count - 1)] : 0.0;
  }
};

/// The trajectory's joint positions `t_s` after its start, for joints that started (at rest) at
/// `start_rad` (joint_count values each). Real-time: no allocation.
void sample_joint_trajectory(const JointTrajectory& trajectory, std::span<const double> start_rad,
                             double t_s, std::span<double> out_rad) noexcept;

/// How close a first point at time 0 must be to where its joint is measured (rad): the loop
/// starts from its command there, so a larger gap would be a jump the sender did not ask for.
inline constexpr double kTrajectoryStartTolerance_rad = 0.02;
/// Trajectories longer than this are refused (an hour: a stamp in nanoseconds, not seconds).
inline constexpr double kMaxTrajectoryDuration_s = 3600.0;

/// Why `trajectory` cannot be carried out from the measured positions `measured_rad` within
/// `limits` (both per trajectory joint), naming the joint (`names`, per trajectory joint), the
/// point and the figure; empty when it can. Checked: counts within capacity, times finite and
/// strictly increasing from >= 0, every position and velocity finite and within its limits, a
/// first point at time 0 within kTrajectoryStartTolerance_rad of the measured position, and the
/// motion between points (from the measured position at rest to the first, then point to point)
/// within the position and velocity limits everywhere, not only at the points: a cubic segment's
/// overshoot and its peak velocity are found in closed form.
std::string check_joint_trajectory(const JointTrajectory& trajectory,
                                   std::span<const hal::JointLimits> limits,
                                   std::span<const double> measured_rad,
                                   std::span<const std::string> names);

}  // namespace cambio::control
