// The synchronised saccade profile against its closed form (the single joint's triangle and
// trapezoid durations) and, numerically, its promises: every joint starts at q0 and ends at q1
// together, never above its velocity or acceleration limit.
#include "cambio/control/saccade_profile.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <random>
#include <vector>

#include "cambio/runtime/allocation_counter.hpp"

namespace cambio::control {
namespace {

TEST(SaccadeProfile, SingleJointTriangleTakesTwoRootsOfDistanceOverAcceleration) {
  // d = 0.1 rad, a = 400 rad/s^2, v = 8 rad/s: v^2 / a = 0.16 > d, so v is never reached.
  SaccadeProfile profile(1);
  const std::vector<double> q0{0.2}, q1{0.3}, v{8.0}, a{400.0};
  const double T = profile.plan(q0, q1, v, a);
  EXPECT_NEAR(T, 2.0 * std::sqrt(0.1 / 400.0), 1e-12);
  // Peak speed at mid-time: a T / 2 = sqrt(a d).
  std::vector<double> q(1), qdot(1);
  profile.sample(T / 2.0, q, qdot);
  EXPECT_NEAR(qdot[0], std::sqrt(400.0 * 0.1), 1e-9);
  EXPECT_NEAR(q[0], 0.25, 1e-12);
}

TEST(SaccadeProfile, SingleJointTrapezoidTakesDistanceOverVelocityPlusVelocityOverAcceleration) {
  // d = 1 rad > v^2 / a = 0.16: trapezoid, cruising at v.
  SaccadeProfile profile(1);
  const std::vector<double> q0{0.5}, q1{-0.5}, v{8.0}, a{400.0};
  const double T = profile.plan(q0, q1, v, a);
  EXPECT_NEAR(T, 1.0 / 8.0 + 8.0 / 400.0, 1e-12);
  std::vector<double> q(1), qdot(1);
  profile.sample(T / 2.0, q, qdot);
  EXPECT_NEAR(qdot[0], -8.0, 1e-9);
  EXPECT_NEAR(q[0], 0.0, 1e-12);
}

TEST(SaccadeProfile, JointsEndTogetherWithinTheirLimits) {
  std::mt19937 rng(9);
  std::uniform_real_distribution<double> position(-0.8, 0.8);
  std::uniform_real_distribution<double> speed(0.5, 8.0);
  std::uniform_real_distribution<double> acceleration(5.0, 400.0);
  constexpr int kJoints = 5;
  SaccadeProfile profile(kJoints);
  std::vector<double> q0(kJoints), q1(kJoints), v(kJoints), a(kJoints);
  std::vector<double> q(kJoints), qdot(kJoints), q_prev(kJoints), qdot_prev(kJoints);
  for (int trial = 0; trial < 50; ++trial) {
    for (int j = 0; j < kJoints; ++j) {
      q0[j] = position(rng);
      q1[j] = trial % 7 == 0 && j == 2 ? q0[j] : position(rng);  // Sometimes one stays.
      v[j] = speed(rng);
      a[j] = acceleration(rng);
    }
    const double T = profile.plan(q0, q1, v, a);
    ASSERT_GT(T, 0.0);
    ASSERT_DOUBLE_EQ(profile.duration_s(), T);
    // The slowest joint alone, in closed form, sets T.
    double slowest_s = 0.0;
    for (int j = 0; j < kJoints; ++j) {
      const double d = std::abs(q1[j] - q0[j]);
      slowest_s = std::max(
          slowest_s, d <= v[j] * v[j] / a[j] ? 2.0 * std::sqrt(d / a[j]) : d / v[j] + v[j] / a[j]);
    }
    EXPECT_NEAR(T, slowest_s, 1e-12);

    profile.sample(0.0, q, qdot);
    for (int j = 0; j < kJoints; ++j) {
      EXPECT_DOUBLE_EQ(q[j], q0[j]);
      EXPECT_DOUBLE_EQ(qdot[j], 0.0);
    }
    profile.sample(T, q, qdot);
    for (int j = 0; j < kJoints; ++j) {
      EXPECT_NEAR(q[j], q1[j], 1e-12);
      EXPECT_DOUBLE_EQ(qdot[j], 0.0);
    }
    // Numerically: finite-difference velocity and acceleration within the limits, and the
    // sampled velocity consistent with the positions.
    constexpr int kSteps = 4000;
    const double dt = T / kSteps;
    profile.sample(0.0, q_prev, qdot_prev);
    for (int k = 1; k <= kSteps; ++k) {
      profile.sample(k * dt, q, qdot);
      for (int j = 0; j < kJoints; ++j) {
        const double fd_velocity = (q[j] - q_prev[j]) / dt;
        ASSERT_LE(std::abs(fd_velocity), v[j] * (1.0 + 1e-9)) << trial << " joint " << j;
        ASSERT_LE(std::abs(qdot[j]), v[j] * (1.0 + 1e-9)) << trial << " joint " << j;
        ASSERT_LE(std::abs(qdot[j] - qdot_prev[j]) / dt, a[j] * (1.0 + 1e-9))
            << trial << " joint " << j;
        // Mean of the end velocities = chord slope for piecewise-constant acceleration, up to
        // the steps that straddle a phase change.
        ASSERT_NEAR(fd_velocity, 0.5 * (qdot[j] + qdot_prev[j]), a[j] * dt) << trial;
      }
      q_prev = q;
      qdot_prev = qdot;
    }
  }
}

TEST(SaccadeProfile, NothingMovingTakesNoTimeAndBadInputKeepsThePlan) {
  SaccadeProfile profile(2);
  const std::vector<double> q0{0.1, 0.2}, q1{0.3, 0.2}, v{1.0, 0.0}, a{10.0, 0.0};
  EXPECT_GT(profile.plan(q0, q1, v, a), 0.0);  // Joint 1 does not move: its zero limits pass.
  const double T = profile.duration_s();
  EXPECT_DOUBLE_EQ(profile.plan(q0, q0, v, a), 0.0);
  EXPECT_TRUE(std::isnan(profile.plan(q0, q1, std::vector<double>{0.0, 1.0}, a)));
  EXPECT_TRUE(std::isnan(profile.plan(q0, std::vector<double>{0.3}, v, a)));
  EXPECT_DOUBLE_EQ(profile.duration_s(), 0.0);  // The last valid plan (q0 to q0) holds.
  profile.plan(q0, q1, v, a);
  EXPECT_DOUBLE_EQ(profile.duration_s(), T);
}

TEST(SaccadeProfile, PlanAndSampleDoNotAllocate) {
  SaccadeProfile profile(5);
  std::vector<double> q0(5, 0.0), q1{0.1, -0.2, 0.3, 0.4, -0.5}, v(5, 2.0), a(5, 20.0);
  std::vector<double> q(5), qdot(5);
  const std::uint64_t before = runtime::thread_allocation_count();
  const double T = profile.plan(q0, q1, v, a);
  profile.sample(T / 3.0, q, qdot);
  EXPECT_EQ(runtime::thread_allocation_count() - before, 0u);
}

}  // namespace
}  // namespace cambio::control
