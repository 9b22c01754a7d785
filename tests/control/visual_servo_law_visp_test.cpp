// The gaze and arm servos' allocation-free laws (control/src/visual_servo_law.hpp) against ViSP's
// own vpServo (control/src/*_visp.cpp, the laws the loops ran before) on random states, many
// seeds: the point's interaction matrix, the fixation law with its secondary task in the null
// space and joints taken out of the task (zeroed columns, as FixationServo blocks a joint at a
// limit), the arm law with its secondary task and vpServo's joint-limit avoidance for joints
// inside, near and beyond their limits. Both must accept and refuse the same states and agree to
// 1e-9 rad/s where they accept, relatively for velocities above 1 rad/s: two SVDs (LAPACK's in
// ViSP, Eigen's Jacobi here) differ by rounding times the task Jacobian's condition number, so a
// nearly singular task (a singular value of 1e-4, asking for 1e4 rad/s, which the loops scale
// down to the joints' limits) agrees to 1e-12 of its velocity, not to 1e-9 rad/s. Then only the
// Eigen laws run without the heap.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdint>
#include <cstdio>
#include <random>

#include "arm_reach_law.hpp"
#include "arm_reach_servo_visp.hpp"
#include "cambio/runtime/allocation_counter.hpp"
#include "fixation_law.hpp"
#include "fixation_servo_visp.hpp"

namespace cambio::control::detail {
namespace {

constexpr int kSeeds = 30;
constexpr int kStatesPerSeed = 400;
constexpr double kTolerance = 1e-9;  // rad/s, or relative above 1 rad/s.

/// How far a law's outputs a are from vpServo's b over the states compared: the largest
/// |a - b| and |a - b| / max(1, |b|) (infinity norms).
struct Agreement {
  int compared = 0;
  double max_difference = 0.0;
  double max_scaled_difference = 0.0;
  void add(const Eigen::Vector4d& a, const Eigen::Vector4d& b) {
    ++compared;
    const double difference = (a - b).cwiseAbs().maxCoeff();
    max_difference = std::max(max_difference, difference);
    max_scaled_difference =
        std::max(max_scaled_difference, difference / std::max(1.0, b.cwiseAbs().maxCoeff()));
  }
  /// Prints the figures (and how many states showed what the test looks for) and holds them to
  /// kTolerance, every state compared.
  void check(const char* law, int shown, const char* showing) const {
    std::printf(
        "%s: %d states (%d %s), max |difference| %.3g, scaled by max(1, |vpServo's|) %.3g\n", law,
        compared, shown, showing, max_difference, max_scaled_difference);
    EXPECT_EQ(compared, kSeeds * kStatesPerSeed);
    EXPECT_LE(max_scaled_difference, kTolerance);
  }
};

double uniform(std::mt19937_64& rng, double lo, double hi) {
  return std::uniform_real_distribution<double>(lo, hi)(rng);
}
bool chance(std::mt19937_64& rng, double p) {
  return std::bernoulli_distribution(p)(rng);
}

TEST(VisualServoLawVisp, ThePointsInteractionMatrixIsVpFeaturePoints) {
  std::mt19937_64 rng(1);
  double max_difference = 0.0;
  for (int i = 0; i < 2000; ++i) {
    const double x = uniform(rng, -3.0, 3.0);
    const double y = uniform(rng, -3.0, 3.0);
    const double Z_m = uniform(rng, 1e-3, 50.0);
    Eigen::Matrix<double, 2, 6> L;
    Eigen::Matrix<double, 2, 6> L_visp;
    ASSERT_TRUE(FixationLaw::interaction(x, y, Z_m, L));
    ASSERT_TRUE(FixationServoVisp::interaction(x, y, Z_m, L_visp));
    max_difference = std::max(max_difference, (L - L_visp).cwiseAbs().maxCoeff());
  }
  EXPECT_EQ(max_difference, 0.0);
  // Where vpFeaturePoint throws: behind the camera, or on its plane.
  for (const double Z_m : {-1.0, 0.0, 5e-7, -5e-7}) {
    Eigen::Matrix<double, 2, 6> L;
    EXPECT_FALSE(FixationLaw::interaction(0.1, 0.2, Z_m, L)) << Z_m;
    EXPECT_FALSE(FixationServoVisp::interaction(0.1, 0.2, Z_m, L)) << Z_m;
  }
}

TEST(VisualServoLawVisp, TheFixationLawIsVpServosOnRandomStates) {
  Agreement agreement;
  int with_blocked_joints = 0;
  for (int seed = 1; seed <= kSeeds; ++seed) {
    std::mt19937_64 rng(static_cast<std::uint64_t>(seed));
    const double gain_per_s = uniform(rng, 0.5, 20.0);
    FixationLaw law(gain_per_s);
    FixationServoVisp visp(gain_per_s);
    for (int state = 0; state < kStatesPerSeed; ++state) {
      // Up to 70 degrees off the axis (FixationServo's kMaxServoAngleRad), 2% exactly centred.
      const bool centred = chance(rng, 0.02);
      const double x = centred ? 0.0 : uniform(rng, -2.75, 2.75);
      const double y = centred ? 0.0 : uniform(rng, -2.75, 2.75);
      const double Z_m = uniform(rng, 0.05, 20.0);
      // A camera Jacobian: translations of tenths of a metre per radian, rotations about one;
      // FixationServo's weights on the neck's columns half the time; joints taken out of the task
      // (their columns and secondary motion zero), all four of them now and then.
      Eigen::Matrix<double, 6, 4> eJe;
      for (int r = 0; r < 6; ++r) {
        for (int c = 0; c < 4; ++c)
          eJe(r, c) = r < 3 ? uniform(rng, -0.3, 0.3) : uniform(rng, -1, 1);
      }
      if (chance(rng, 0.5)) eJe.leftCols<2>() *= 0.1;
      Eigen::Vector4d u2;
      for (int c = 0; c < 4; ++c) u2(c) = chance(rng, 0.5) ? uniform(rng, -3.0, 3.0) : 0.0;
      bool blocked = false;
      for (int c = 0; c < 4; ++c) {
        if (chance(rng, 0.2)) {
          eJe.col(c).setZero();
          u2(c) = 0.0;
          blocked = true;
        }
      }
      Eigen::Vector4d u;
      Eigen::Vector4d u_visp;
      const bool ok = law.control_law(x, y, Z_m, eJe, u2, u);
      const bool ok_visp = visp.control_law(x, y, Z_m, eJe, u2, u_visp) && u_visp.allFinite();
      ASSERT_EQ(ok, ok_visp) << "seed " << seed << " state " << state;
      if (!ok) continue;
      if (blocked) ++with_blocked_joints;
      agreement.add(u, u_visp);
    }
  }
  agreement.check("fixation law", with_blocked_joints, "with joints out of the task");
  EXPECT_GT(with_blocked_joints, agreement.compared / 4);
}

TEST(VisualServoLawVisp, TheArmLawWithJointLimitAvoidanceIsVpServosOnRandomStates) {
  Agreement agreement;
  int avoiding = 0;  // States where vpServo's joint-limit avoidance changed the velocity.
  for (int seed = 1; seed <= kSeeds; ++seed) {
    std::mt19937_64 rng(static_cast<std::uint64_t>(1000 + seed));
    const double gain_per_s = uniform(rng, 0.5, 10.0);
    ArmReachLaw law(gain_per_s);
    ArmReachServoVisp visp(gain_per_s);
    Eigen::Vector4d q_min;
    Eigen::Vector4d q_max;
    for (int k = 0; k < 4; ++k) {
      q_min(k) = uniform(rng, -2.5, 0.0);
      q_max(k) = q_min(k) + uniform(rng, 0.5, 4.0);
    }
    const Eigen::Vector4d q_middle = 0.5 * (q_min + q_max);
    for (int state = 0; state < kStatesPerSeed; ++state) {
      // The fingertips' error: from the goal (1% exactly there) to a metre, across both ends of
      // the large projection operator's blend (|e| 0.1 to 0.7).
      Eigen::Vector3d e_W(uniform(rng, -1, 1), uniform(rng, -1, 1), uniform(rng, -1, 1));
      e_W *= chance(rng, 0.01) ? 0.0 : uniform(rng, 0.0, 1.0) / e_W.norm();
      Eigen::Matrix<double, 3, 4> J_v;
      for (int r = 0; r < 3; ++r) {
        for (int c = 0; c < 4; ++c) J_v(r, c) = uniform(rng, -0.6, 0.6);
      }
      Eigen::Vector4d u2;
      for (int c = 0; c < 4; ++c) u2(c) = uniform(rng, -1.0, 1.0);
      for (int c = 0; c < 4; ++c) {
        if (chance(rng, 0.1)) {
          J_v.col(c).setZero();
          u2(c) = 0.0;
        }
      }
      // Joints anywhere from 5% of their range beyond a limit to inside it: the avoidance's bands
      // are the 10% next to each limit, fully on in the 7% nearest and beyond.
      Eigen::Vector4d q;
      for (int k = 0; k < 4; ++k) {
        const double range = q_max(k) - q_min(k);
        q(k) = uniform(rng, q_min(k) - 0.05 * range, q_max(k) + 0.05 * range);
      }
      Eigen::Vector4d qdot;
      Eigen::Vector4d qdot_visp;
      const bool ok = law.control_law(e_W, J_v, u2, q, q_min, q_max, qdot);
      const bool ok_visp =
          visp.control_law(e_W, J_v, u2, q, q_min, q_max, qdot_visp) && qdot_visp.allFinite();
      ASSERT_EQ(ok, ok_visp) << "seed " << seed << " state " << state;
      if (!ok) continue;
      agreement.add(qdot, qdot_visp);
      Eigen::Vector4d qdot_free;  // The same law with every joint in the middle of its range.
      ASSERT_TRUE(visp.control_law(e_W, J_v, u2, q_middle, q_min, q_max, qdot_free));
      if ((qdot_free - qdot_visp).cwiseAbs().maxCoeff() > 1e-12) ++avoiding;
    }
  }
  agreement.check("arm law", avoiding, "avoiding a joint limit");
  EXPECT_GT(avoiding, agreement.compared / 10);
}

TEST(VisualServoLawVisp, OnlyTheEigenLawsRunWithoutTheHeap) {
  const double gain_per_s = 4.0;
  FixationLaw fixation(gain_per_s);
  FixationServoVisp fixation_visp(gain_per_s);
  ArmReachLaw arm(gain_per_s);
  ArmReachServoVisp arm_visp(gain_per_s);
  Eigen::Matrix<double, 6, 4> eJe = Eigen::Matrix<double, 6, 4>::Identity();
  eJe(0, 3) = 0.1;
  const Eigen::Vector4d u2(0.2, 0.0, 0.0, 0.0);
  Eigen::Matrix<double, 3, 4> J_v = Eigen::Matrix<double, 3, 4>::Identity();
  J_v(2, 3) = 0.3;
  const Eigen::Vector3d e_W(0.1, -0.2, 0.05);
  const Eigen::Vector4d q_min = Eigen::Vector4d::Constant(-1.0);
  const Eigen::Vector4d q_max = Eigen::Vector4d::Constant(1.0);
  const Eigen::Vector4d q(0.95, 0.0, -0.85, 0.2);  // Two joints in the avoidance's bands.
  Eigen::Vector4d out;

  std::uint64_t before = runtime::thread_allocation_count();
  ASSERT_TRUE(fixation.control_law(0.3, -0.2, 1.5, eJe, u2, out));
  ASSERT_TRUE(arm.control_law(e_W, J_v, u2, q, q_min, q_max, out));
  const std::uint64_t eigen_allocations = runtime::thread_allocation_count() - before;
  before = runtime::thread_allocation_count();
  ASSERT_TRUE(fixation_visp.control_law(0.3, -0.2, 1.5, eJe, u2, out));
  ASSERT_TRUE(arm_visp.control_law(e_W, J_v, u2, q, q_min, q_max, out));
  const std::uint64_t visp_allocations = runtime::thread_allocation_count() - before;

  EXPECT_EQ(eigen_allocations, 0u);
  // The counter sees vpServo's malloc calls (vpArray2D allocates with malloc, not new).
  EXPECT_GT(visp_allocations, 50u);
  std::printf("allocations per law: Eigen %llu, vpServo %llu (fixation and arm laws)\n",
              static_cast<unsigned long long>(eigen_allocations),
              static_cast<unsigned long long>(visp_allocations));
}

}  // namespace
}  // namespace cambio::control::detail
