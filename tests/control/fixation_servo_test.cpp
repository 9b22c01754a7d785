// The fixation servo on the shipped rig's model (no sim): its feature Jacobian against finite
// differences of the projection through Kinematics, and the law integrated at 200 Hz (Euler,
// positions clamped to the limits as the joint loop clamps them) against closed forms: a small
// gaze shift is the eye's alone and ends at the atan2 pan, a large one turns the neck until both
// eyes are inside the 30° rule, a target beyond the eye's limit is reached by the neck without
// wind-up; solve() ends where the integration ends.
#include "cambio/control/fixation_servo.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <numbers>
#include <random>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include "cambio/config/hardware_description.hpp"
#include "cambio/config/rig_loader.hpp"
#include "cambio/config/shipped_config.hpp"

namespace cambio::control {
namespace {

using std::numbers::pi;
constexpr double kDeg = pi / 180.0;
constexpr double kControlPeriodS = 1.0 / 200.0;

hal::HardwareInfo shipped_rig() {
  return config::hardware_description(
      config::load_rig(config::find_shipped_config("rigs/cambio.yaml")));
}

FixationParams params(hal::Eye dominant = hal::Eye::kLeft, double neck_rule_rad = 30.0 * kDeg) {
  FixationParams p;
  p.dominant_eye = dominant;
  p.gain_per_s = 5.0;
  p.neck_rule_rad = neck_rule_rad;
  p.default_depth_m = 1.0;
  return p;
}

/// (x, y) of p_W in a camera of `kinematics` at q: the projection, independent of the servo.
Eigen::Vector2d project(Kinematics& kinematics, const Eigen::VectorXd& q, int camera,
                        const Eigen::Vector3d& p_W) {
  EXPECT_EQ(kinematics.update(q), hal::Status::kOk);
  const Eigen::Vector3d p_C = kinematics.X_WF(camera).inverse() * p_W;
  return {p_C.x() / p_C.z(), p_C.y() / p_C.z()};
}

class FixationServoTest : public ::testing::Test {
 protected:
  FixationServoTest() : hardware_(shipped_rig()), kinematics_(hardware_) {}

  Eigen::VectorXd zero_q() const { return Eigen::VectorXd::Zero(kinematics_.joint_count()); }

  /// A point `distance_m` from the eye pan axis of `eye` at q = 0, `azimuth_rad` to the left
  /// (negative: right) in the horizontal plane of the eye.
  Eigen::Vector4d target_beside(hal::Eye eye, double azimuth_rad, double distance_m) {
    const HeadJoints head = find_head_joints(kinematics_, hardware_);
    EXPECT_EQ(kinematics_.update(zero_q()), hal::Status::kOk);
    const Eigen::Vector3d origin_W =
        kinematics_.X_WF(Kinematics::link_frame(head.pan(eye))).translation();
    Eigen::Vector4d target;
    target << origin_W +
                  distance_m * Eigen::Vector3d(std::cos(azimuth_rad), std::sin(azimuth_rad), 0.0),
        1.0;
    return target;
  }

  struct Run {
    Eigen::VectorXd q;
    FixationError error;
    double max_abs_neck_move_rad = 0.0;  ///< Largest excursion of neck pan or tilt from q0.
    int wind_up_steps = 0;               ///< Steps commanding a joint at a limit further out.
  };

  /// Euler at 200 Hz for `duration_s`, positions clamped to the joint limits.
  Run integrate(FixationServo& servo, Eigen::VectorXd q, const Eigen::Vector4d& target_W,
                double vergence_rad, double duration_s) {
    Run run;
    const Eigen::VectorXd q0 = q;
    std::vector<double> qdot(q.size());
    const HeadJoints& head = servo.head();
    const auto steps = static_cast<int>(std::lround(duration_s / kControlPeriodS));
    for (int k = 0; k < steps; ++k) {
      EXPECT_EQ(servo.velocity(std::span<const double>(q.data(), q.size()), target_W, vergence_rad,
                               qdot, &run.error),
                hal::Status::kOk);
      for (int j = 0; j < q.size(); ++j) {
        const hal::JointLimits& limits = hardware_.joints[static_cast<std::size_t>(j)].limits;
        if ((q[j] >= limits.max_position_rad && qdot[j] > 0.0) ||
            (q[j] <= limits.min_position_rad && qdot[j] < 0.0)) {
          ++run.wind_up_steps;
        }
        q[j] = std::clamp(q[j] + kControlPeriodS * qdot[j], limits.min_position_rad,
                          limits.max_position_rad);
      }
      for (const int neck : {head.neck_pan, head.neck_tilt}) {
        run.max_abs_neck_move_rad =
            std::max(run.max_abs_neck_move_rad, std::abs(q[neck] - q0[neck]));
      }
    }
    run.error = servo.error(std::span<const double>(q.data(), q.size()), target_W);
    run.q = q;
    return run;
  }

  hal::HardwareInfo hardware_;
  Kinematics kinematics_;
};

TEST_F(FixationServoTest, FeatureJacobianIsTheDerivativeOfTheProjection) {
  std::mt19937 rng(3);
  for (const hal::Eye dominant : {hal::Eye::kLeft, hal::Eye::kRight}) {
    FixationServo servo(hardware_, params(dominant));
    const int camera = servo.head().camera(dominant);
    for (int trial = 0; trial < 20; ++trial) {
      Eigen::VectorXd q = zero_q();
      for (const int j : servo.servoed_joints()) {
        const hal::JointLimits& limits = hardware_.joints[static_cast<std::size_t>(j)].limits;
        q[j] = std::uniform_real_distribution<double>(limits.min_position_rad,
                                                      limits.max_position_rad)(rng);
      }
      // A point in the camera's field of view, 0.3 to 3 m deep.
      ASSERT_EQ(kinematics_.update(q), hal::Status::kOk);
      const Eigen::Vector3d p_C(std::uniform_real_distribution<double>(-0.5, 0.5)(rng),
                                std::uniform_real_distribution<double>(-0.4, 0.4)(rng), 1.0);
      const Eigen::Vector3d p_W =
          kinematics_.X_WF(camera) * (p_C * std::uniform_real_distribution<double>(0.3, 3.0)(rng));
      const Eigen::Vector4d target(p_W.x(), p_W.y(), p_W.z(), 1.0);

      Eigen::Matrix<double, 2, FixationServo::kServoed> J;
      ASSERT_EQ(servo.feature_jacobian(std::span<const double>(q.data(), q.size()), target, J),
                hal::Status::kOk);
      constexpr double kStepRad = 1e-6;
      for (int c = 0; c < FixationServo::kServoed; ++c) {
        Eigen::VectorXd plus = q, minus = q;
        plus[servo.servoed_joints()[c]] += kStepRad;
        minus[servo.servoed_joints()[c]] -= kStepRad;
        const Eigen::Vector2d numeric =
            (project(kinematics_, plus, camera, p_W) - project(kinematics_, minus, camera, p_W)) /
            (2.0 * kStepRad);
        EXPECT_NEAR((J.col(c) - numeric).norm(), 0.0, 1e-6)
            << "trial " << trial << " column " << c << ": servo " << J.col(c).transpose()
            << ", finite differences " << numeric.transpose();
      }
    }
  }
}

TEST_F(FixationServoTest, TenDegreesLeftIsTheDominantEyesAlone) {
  FixationServo servo(hardware_, params());
  const Eigen::Vector4d target = target_beside(hal::Eye::kLeft, 10.0 * kDeg, 1.0);
  const Run run = integrate(servo, zero_q(), target, 0.0, 3.0);
  EXPECT_LT(std::hypot(run.error.x, run.error.y), 1e-6);
  EXPECT_LT(run.max_abs_neck_move_rad, 0.5 * kDeg);

  // Closed form at the final pose: the optical axis runs along the pan link's x through the pan
  // axis, so the centred pan is the target's azimuth about the pan joint in the eye tilt's frame.
  const HeadJoints& head = servo.head();
  const int pan = head.pan(hal::Eye::kLeft);
  ASSERT_EQ(kinematics_.update(run.q), hal::Status::kOk);
  const Eigen::Vector3d p_T =
      kinematics_.X_WF(Kinematics::link_frame(head.eye_tilt)).inverse() * target.head<3>();
  const Eigen::Vector3d p_J =
      p_T - hardware_.joints[static_cast<std::size_t>(pan)].X_PJ.translation();
  EXPECT_NEAR(run.q[pan], std::atan2(p_J.y(), p_J.x()), 1e-3);
  EXPECT_NEAR(run.q[pan], 10.0 * kDeg, 0.5 * kDeg);
}

struct NeckRuleCase {
  hal::Eye dominant;
  double side;  ///< +1 left, -1 right.
  double vergence_rad;
};

class NeckRule : public FixationServoTest, public ::testing::WithParamInterface<NeckRuleCase> {};

TEST_P(NeckRule, FiftyDegreesAwayEndsCentredWithBothEyesInsideTheRule) {
  const NeckRuleCase c = GetParam();
  FixationServo servo(hardware_, params(c.dominant));
  const Eigen::Vector4d target = target_beside(c.dominant, c.side * 50.0 * kDeg, 1.5);
  const Run run = integrate(servo, zero_q(), target, c.vergence_rad, 6.0);
  EXPECT_TRUE(run.error.in_front);
  EXPECT_LT(std::hypot(run.error.x, run.error.y), 1e-3);
  const double dominant_pan = run.q[servo.head().pan(c.dominant)];
  const double verging_pan =
      dominant_pan + (c.dominant == hal::Eye::kLeft ? 1.0 : -1.0) * c.vergence_rad;
  EXPECT_LE(std::abs(dominant_pan), 30.0 * kDeg);
  EXPECT_LE(std::abs(verging_pan), 30.0 * kDeg);
  // The neck turned towards the target by (nearly) the excess.
  EXPECT_GT(c.side * run.q[servo.head().neck_pan], 15.0 * kDeg);
  EXPECT_EQ(run.wind_up_steps, 0);
}

INSTANTIATE_TEST_SUITE_P(Cases, NeckRule,
                         ::testing::Values(NeckRuleCase{hal::Eye::kLeft, 1.0, 0.0},
                                           NeckRuleCase{hal::Eye::kLeft, 1.0, 5.0 * kDeg},
                                           NeckRuleCase{hal::Eye::kLeft, -1.0, 5.0 * kDeg},
                                           NeckRuleCase{hal::Eye::kRight, 1.0, 5.0 * kDeg},
                                           NeckRuleCase{hal::Eye::kRight, -1.0, 0.0}));

TEST_F(FixationServoTest, BeyondTheEyesLimitTheNeckTakesOverWithoutWindUp) {
  // The rule disabled: the eye alone would need 48°, beyond its 45° limit.
  FixationServo servo(hardware_, params(hal::Eye::kLeft, 10.0));
  const Eigen::Vector4d target = target_beside(hal::Eye::kLeft, 48.0 * kDeg, 1.0);
  const Run run = integrate(servo, zero_q(), target, 0.0, 4.0);
  const int pan = servo.head().pan(hal::Eye::kLeft);
  EXPECT_DOUBLE_EQ(run.q[pan], 45.0 * kDeg);
  EXPECT_EQ(run.wind_up_steps, 0);
  EXPECT_LT(std::hypot(run.error.x, run.error.y), 1e-3);
  EXPECT_GT(run.q[servo.head().neck_pan], 2.0 * kDeg);

  // At the limit with the target still to the left: the eye is not pushed further.
  Eigen::VectorXd q = zero_q();
  q[pan] = 45.0 * kDeg;
  std::vector<double> qdot(q.size());
  ASSERT_EQ(servo.velocity(std::span<const double>(q.data(), q.size()), target, 0.0, qdot),
            hal::Status::kOk);
  EXPECT_EQ(qdot[pan], 0.0);
  EXPECT_GT(qdot[servo.head().neck_pan], 0.0);
}

TEST_F(FixationServoTest, TheVergingEyesLimitBoundsTheDominantEye) {
  // Right eye verging 10° inwards of the left (right = left + 10°, limit 45°): the left may pan
  // to 35° only. The integration clamps each joint to its own limits, so the dominant eye may
  // pass 35° by at most one step before it is held.
  FixationServo servo(hardware_, params(hal::Eye::kLeft, 10.0));
  const int pan = servo.head().pan(hal::Eye::kLeft);
  const Eigen::Vector4d target = target_beside(hal::Eye::kLeft, 40.0 * kDeg, 1.0);
  const Run run = integrate(servo, zero_q(), target, 10.0 * kDeg, 4.0);
  EXPECT_GE(run.q[pan], 35.0 * kDeg - 1e-9);
  EXPECT_LE(run.q[pan], 35.0 * kDeg + 8.0 * kControlPeriodS);  // Eye max velocity 8 rad/s.
  EXPECT_LT(std::hypot(run.error.x, run.error.y), 1e-3);

  Eigen::VectorXd q = zero_q();
  q[pan] = 35.0 * kDeg;
  std::vector<double> qdot(q.size());
  ASSERT_EQ(servo.velocity(std::span<const double>(q.data(), q.size()), target, 10.0 * kDeg, qdot),
            hal::Status::kOk);
  EXPECT_EQ(qdot[pan], 0.0);
  EXPECT_GT(qdot[servo.head().neck_pan], 0.0);
  // Without vergence the same pose leaves the eye free.
  ASSERT_EQ(servo.velocity(std::span<const double>(q.data(), q.size()), target, 0.0, qdot),
            hal::Status::kOk);
  EXPECT_GT(qdot[pan], 0.0);
}

TEST_F(FixationServoTest, SolveEndsWhereTheIntegratedLawEnds) {
  for (const double azimuth_deg : {10.0, -25.0, 50.0}) {
    FixationServo servo(hardware_, params());
    const Eigen::Vector4d target = target_beside(hal::Eye::kLeft, azimuth_deg * kDeg, 1.2);
    const double vergence_rad = 4.0 * kDeg;
    const Run run = integrate(servo, zero_q(), target, vergence_rad, 8.0);
    const Eigen::VectorXd q_start = zero_q();
    std::vector<double> q_solved(q_start.size());
    ASSERT_EQ(servo.solve(std::span<const double>(q_start.data(), q_start.size()), target,
                          vergence_rad, q_solved),
              hal::Status::kOk);
    const FixationError error = servo.error(q_solved, target);
    EXPECT_LT(std::hypot(error.x, error.y), 1e-6);
    for (const int j : servo.servoed_joints()) {
      // The same law on another time grid: the same path (measured: 2e-6 rad apart).
      EXPECT_NEAR(q_solved[static_cast<std::size_t>(j)], run.q[j], 1e-4)
          << azimuth_deg << "° " << kinematics_.joint_name(j);
    }
    const int right = servo.head().pan(hal::Eye::kRight);
    const int left = servo.head().pan(hal::Eye::kLeft);
    EXPECT_NEAR(
        q_solved[static_cast<std::size_t>(right)] - q_solved[static_cast<std::size_t>(left)],
        vergence_rad, 1e-12);
  }
}

TEST_F(FixationServoTest, SolveRefusesATargetOutOfReach) {
  FixationServo servo(hardware_, params());
  // Straight behind the head: beyond neck pan 90° plus eye pan 45°.
  Eigen::Vector4d target(-2.0, 0.0, 1.4, 1.0);
  const Eigen::VectorXd q = zero_q();
  std::vector<double> q_out(q.size());
  EXPECT_EQ(servo.solve(std::span<const double>(q.data(), q.size()), target, 0.0, q_out),
            hal::Status::kRejected);
}

TEST_F(FixationServoTest, PixelRayProjectsBackOntoItsPixel) {
  FixationServo servo(hardware_, params(hal::Eye::kRight));
  const hal::CameraIntrinsics& K = hardware_.find_camera("right_eye")->intrinsics;
  Eigen::VectorXd q = zero_q();
  q[servo.head().neck_pan] = 0.3;
  q[servo.head().eye_tilt] = -0.2;
  q[servo.head().pan(hal::Eye::kRight)] = 0.1;
  const std::span<const double> q_span(q.data(), q.size());
  const int camera = servo.head().camera(hal::Eye::kRight);
  for (const auto& [u, v] : {std::pair{K.principal_x_px, K.principal_y_px}, std::pair{10.0, 470.0},
                             std::pair{600.0, 35.0}}) {
    const Eigen::Vector3d ray_W = servo.pixel_ray_W(q_span, u, v);
    EXPECT_NEAR(ray_W.norm(), 1.0, 1e-12);
    ASSERT_EQ(kinematics_.update(q), hal::Status::kOk);
    const Eigen::Vector3d p_W = kinematics_.X_WF(camera).translation() + 2.0 * ray_W;
    const Eigen::Vector2d xy = project(kinematics_, q, camera, p_W);
    EXPECT_NEAR(K.focal_x_px * xy.x() + K.principal_x_px, u, 1e-9);
    EXPECT_NEAR(K.focal_y_px * xy.y() + K.principal_y_px, v, 1e-9);
    // And the servo's own error of that point is the pixel's offset from the principal point.
    const FixationError error = servo.error(q_span, Eigen::Vector4d(p_W.x(), p_W.y(), p_W.z(), 1));
    EXPECT_NEAR(error.error_px, std::hypot(u - K.principal_x_px, v - K.principal_y_px), 1e-6);
    // A direction target (w = 0) along the ray is the same image point.
    const FixationError direction =
        servo.error(q_span, Eigen::Vector4d(ray_W.x(), ray_W.y(), ray_W.z(), 0.0));
    EXPECT_NEAR(direction.x, error.x, 1e-12);
    EXPECT_NEAR(direction.y, error.y, 1e-12);
  }
}

TEST_F(FixationServoTest, RefusesBadInputAndUnsetParameters) {
  FixationServo servo(hardware_, params());
  std::vector<double> q(3, 0.0), qdot(kinematics_.joint_count(), 1.0);
  EXPECT_EQ(servo.velocity(q, Eigen::Vector4d(1, 0, 1.4, 1), 0.0, qdot), hal::Status::kRejected);
  for (const double v : qdot) EXPECT_EQ(v, 0.0);
  EXPECT_THROW(FixationServo(hardware_, FixationParams{}), std::invalid_argument);
  FixationParams no_depth = params();
  no_depth.default_depth_m = 0.0;
  EXPECT_THROW(FixationServo(hardware_, no_depth), std::invalid_argument);
}

}  // namespace
}  // namespace cambio::control
