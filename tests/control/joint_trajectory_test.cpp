// Joint trajectories against closed forms: linear and cubic Hermite interpolation as ROS's
// joint_trajectory_controller defines them, the start from rest, and the check's refusals (each
// with a trajectory that breaks one rule, and the figure it names).
#include "cambio/control/joint_trajectory.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <string>
#include <vector>

#include "cambio/control/joint_trajectory_follower.hpp"

namespace cambio::control {
namespace {

JointTrajectory one_joint(std::vector<double> times, std::vector<double> positions,
                          std::vector<double> velocities = {}) {
  JointTrajectory trajectory;
  trajectory.sequence = 1;
  trajectory.joint_count = 1;
  trajectory.point_count = static_cast<int>(times.size());
  trajectory.has_velocities = !velocities.empty();
  for (std::size_t k = 0; k < times.size(); ++k) {
    trajectory.time_from_start_s[k] = times[k];
    trajectory.positions_rad[k][0] = positions[k];
    if (!velocities.empty()) trajectory.velocities_rad_s[k][0] = velocities[k];
  }
  return trajectory;
}

double sample(const JointTrajectory& trajectory, double start_rad, double t_s) {
  const std::vector<double> start{start_rad};
  std::vector<double> out(1);
  sample_joint_trajectory(trajectory, start, t_s, out);
  return out[0];
}

const hal::JointLimits kLimits{-1.0, 1.0, 2.0, 10.0, 0.0};

std::string check(const JointTrajectory& trajectory, double measured_rad,
                  hal::JointLimits limits = kLimits) {
  const std::vector<hal::JointLimits> all(1, limits);
  const std::vector<double> measured{measured_rad};
  const std::vector<std::string> names{"neck_pan"};
  return check_joint_trajectory(trajectory, all, measured, names);
}

TEST(JointTrajectory, PositionsOnlyAreLinearFromTheStartThenBetweenPoints) {
  const JointTrajectory trajectory = one_joint({1.0, 3.0}, {0.5, -0.5});
  EXPECT_DOUBLE_EQ(sample(trajectory, 0.1, 0.0), 0.1);
  EXPECT_DOUBLE_EQ(sample(trajectory, 0.1, 0.5), 0.3);
  EXPECT_DOUBLE_EQ(sample(trajectory, 0.1, 1.0), 0.5);
  EXPECT_DOUBLE_EQ(sample(trajectory, 0.1, 2.5), -0.25);
  EXPECT_DOUBLE_EQ(sample(trajectory, 0.1, 3.0), -0.5);
  EXPECT_DOUBLE_EQ(sample(trajectory, 0.1, 100.0), -0.5);  // Holds the last point.
}

TEST(JointTrajectory, VelocitiesGiveTheCubicHermiteSplineStartingAtRest) {
  // From rest at 0 to 0.2 rad at rest in 1 s: q = 0.2 (3 s^2 - 2 s^3).
  const JointTrajectory rest_to_rest = one_joint({1.0}, {0.2}, {0.0});
  for (const double t : {0.0, 0.25, 0.5, 0.75, 1.0}) {
    EXPECT_NEAR(sample(rest_to_rest, 0.0, t), 0.2 * (3 * t * t - 2 * t * t * t), 1e-15) << t;
  }
  // Then on to 0.6 rad at 0.4 rad/s over 2 s: the Hermite basis at s = 0.5 gives
  // q0/2 + h m0/8 + q1/2 - h m1/8 with m the velocities: 0.1 + 0 + 0.3 - 2 * 0.4 / 8 = 0.3.
  const JointTrajectory two = one_joint({1.0, 3.0}, {0.2, 0.6}, {0.0, 0.4});
  EXPECT_NEAR(sample(two, 0.0, 2.0), 0.3, 1e-15);
  // Its velocity at the end is the one asked for: a finite difference.
  const double h = 1e-6;
  EXPECT_NEAR((sample(two, 0.0, 3.0 - h) - sample(two, 0.0, 3.0 - 2 * h)) / h, 0.4, 1e-5);
}

TEST(JointTrajectory, AFirstPointAtTimeZeroIsTheStartNoJump) {
  const JointTrajectory trajectory = one_joint({0.0, 1.0}, {0.01, 0.5});
  EXPECT_DOUBLE_EQ(sample(trajectory, 0.0, 0.0), 0.0);
  EXPECT_DOUBLE_EQ(sample(trajectory, 0.0, 0.5), 0.25);
  EXPECT_EQ(check(trajectory, 0.0), "");
  EXPECT_EQ(check(trajectory, 0.1),
            "joint neck_pan: point 0 (0 s) is 0.09 rad from where the joint is (a jump; more "
            "than 0.02 rad)");
}

TEST(JointTrajectory, TheCheckNamesWhatIsWrong) {
  const double nan = std::numeric_limits<double>::quiet_NaN();
  EXPECT_EQ(check(one_joint({0.5, 1.0}, {0.2, 0.4}), 0.0), "");
  EXPECT_EQ(check(one_joint({0.5, 0.5}, {0.2, 0.4}), 0.0),
            "point 1 (0.5 s): not after point 0 (0.5 s) (times must increase)");
  EXPECT_EQ(check(one_joint({nan}, {0.2}), 0.0),
            "point 0 (nan s): a time from start must be within [0, 3600] s");
  EXPECT_EQ(check(one_joint({1.0}, {nan}), 0.0),
            "joint neck_pan, point 0 (1 s): position nan rad is not within its limits [-1, 1] "
            "rad");
  EXPECT_EQ(check(one_joint({1.0}, {1.5}), 0.0),
            "joint neck_pan, point 0 (1 s): position 1.5 rad is not within its limits [-1, 1] "
            "rad");
  EXPECT_EQ(check(one_joint({1.0}, {0.5}, {3.0}), 0.0),
            "joint neck_pan, point 0 (1 s): velocity 3 rad/s is beyond its 2 rad/s limit");
  // Too fast from where the joint is: 0.9 rad in 0.3 s.
  EXPECT_EQ(check(one_joint({0.3}, {0.9}), 0.0),
            "joint neck_pan: from where it is to point 0 (0.3 s): 3 rad/s, above its 2 rad/s "
            "limit");
  // A cubic's peak velocity between points: rest to rest over 0.8 rad in 0.5 s peaks at
  // 1.5 x 0.8 / 0.5 = 2.4 rad/s, though the average is 1.6.
  EXPECT_EQ(check(one_joint({0.5}, {0.8}, {0.0}), 0.0),
            "joint neck_pan: from where it is to point 0 (0.5 s): 2.4 rad/s, above its 2 rad/s "
            "limit");
  // Points inside the limits, the spline through them not: 0.95 -> 0.95 leaving at 1 rad/s over
  // 1 s peaks at 0.95 + 4/27 (the Hermite term h m0 s (1 - s)^2 at s = 1/3).
  EXPECT_EQ(check(one_joint({1.0, 2.0}, {0.95, 0.95}, {1.0, 0.0}), 0.95),
            "joint neck_pan: from point 0 (1 s) to point 1 (2 s): the spline overshoots to 1.098 "
            "rad, beyond its limits [-1, 1] rad");
  // Counts beyond the capacity are refused before anything is read.
  JointTrajectory too_long = one_joint({1.0}, {0.5});
  too_long.point_count = JointTrajectory::kMaxPoints + 1;
  EXPECT_EQ(check(too_long, 0.0), "129 points: a trajectory has 1 to 128");
}

TEST(JointTrajectory, TheFollowerWritesItsJointsOnlyAndStopsAtTheLastPoint) {
  JointTrajectory trajectory = one_joint({1.0}, {0.5});
  trajectory.joint_rig_index[0] = 2;
  const std::vector<int> rig_to_tree{3, 0, 1, 2};  // Rig joint 2 is tree joint 1.
  std::vector<double> q_tree{0.0, 0.1, 0.0, 0.0};
  JointTrajectoryFollower follower;
  follower.start(trajectory, rig_to_tree, q_tree, 1'000'000'000);
  EXPECT_TRUE(follower.drives(1));
  EXPECT_FALSE(follower.drives(2));
  EXPECT_TRUE(follower.step(1'500'000'000, q_tree));
  EXPECT_DOUBLE_EQ(q_tree[1], 0.3);
  EXPECT_EQ(q_tree[0] + q_tree[2] + q_tree[3], 0.0);
  EXPECT_FALSE(follower.step(2'000'000'000, q_tree));
  EXPECT_DOUBLE_EQ(q_tree[1], 0.5);
  EXPECT_FALSE(follower.active());
  EXPECT_EQ(follower.finished(), 1u);
}

}  // namespace
}  // namespace cambio::control
