#include "arm_reach_servo_visp.hpp"

#include <visp3/core/vpColVector.h>
#include <visp3/core/vpMatrix.h>
#include <visp3/core/vpVelocityTwistMatrix.h>
#include <visp3/visual_features/vpFeaturePoint3D.h>
#include <visp3/vs/vpServo.h>

namespace cambio::control::detail {
namespace {

// vpFeaturePoint3D is a camera's point and refuses Z = 0, which a target at the fingertips would
// be: T is placed this far below them (the target seen at Z = kZOffset_m + e_z, never 0 within an
// arm's reach). With w_T = 0 the offset changes nothing: L eJe = -J_v at any point.
constexpr double kZOffset_m = 10.0;

}  // namespace

struct ArmReachServoVisp::Task {
  // vpServo keeps pointers to the features: they are declared first, destroyed last.
  vpFeaturePoint3D s;
  vpFeaturePoint3D s_star;
  vpServo servo;
  // Not brace-initialised: ViSP's arrays take a brace list as their elements.
  vpMatrix eJe = vpMatrix(6, 4);
  vpColVector u2 = vpColVector(4);
  vpColVector q = vpColVector(4);
  vpColVector q_min = vpColVector(4);
  vpColVector q_max = vpColVector(4);
};

ArmReachServoVisp::ArmReachServoVisp(double gain_per_s) : task_(std::make_unique<Task>()) {
  Task& t = *task_;
  t.s.buildFrom(0.0, 0.0, kZOffset_m);
  t.s_star.buildFrom(0.0, 0.0, kZOffset_m);
  t.servo.setServo(vpServo::EYEINHAND_L_cVe_eJe);
  t.servo.setInteractionMatrixType(vpServo::CURRENT, vpServo::PSEUDO_INVERSE);
  t.servo.setLambda(gain_per_s);
  t.servo.set_cVe(vpVelocityTwistMatrix());
  t.servo.set_eJe(t.eJe);
  t.servo.addFeature(t.s, t.s_star);
}

ArmReachServoVisp::~ArmReachServoVisp() = default;

bool ArmReachServoVisp::control_law(const Eigen::Vector3d& e_W,
                                    const Eigen::Matrix<double, 3, 4>& J_v,
                                    const Eigen::Vector4d& u2, const Eigen::Vector4d& q_rad,
                                    const Eigen::Vector4d& q_min_rad,
                                    const Eigen::Vector4d& q_max_rad, Eigen::Vector4d& qdot) {
  Task& t = *task_;
  try {
    t.s.buildFrom(e_W.x(), e_W.y(), kZOffset_m + e_W.z());
    for (unsigned r = 0; r < 3; ++r) {
      for (unsigned c = 0; c < 4; ++c) {
        t.eJe[r][c] = J_v(r, c);
        t.eJe[r + 3][c] = 0.0;  // T keeps the base's axes: no angular velocity.
      }
    }
    for (unsigned c = 0; c < 4; ++c) {
      t.u2[c] = u2(c);
      t.q[c] = q_rad(c);
      t.q_min[c] = q_min_rad(c);
      t.q_max[c] = q_max_rad(c);
    }
    t.servo.set_eJe(t.eJe);
    const vpColVector u1 = t.servo.computeControlLaw();
    const vpColVector u = u1 + t.servo.secondaryTask(t.u2);
    const vpColVector u_limits = t.servo.secondaryTaskJointLimitAvoidance(t.q, u, t.q_min, t.q_max);
    for (unsigned c = 0; c < 4; ++c) qdot(c) = u[c] + u_limits[c];
  } catch (...) {  // vpException: a task ViSP cannot serve.
    return false;
  }
  return true;
}

}  // namespace cambio::control::detail
