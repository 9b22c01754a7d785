#include "fixation_servo_visp.hpp"

#include <visp3/core/vpColVector.h>
#include <visp3/core/vpMatrix.h>
#include <visp3/core/vpVelocityTwistMatrix.h>
#include <visp3/visual_features/vpFeaturePoint.h>
#include <visp3/vs/vpServo.h>

namespace cambio::control::detail {

struct FixationServoVisp::Task {
  // vpServo keeps pointers to the features: they are declared first, destroyed last.
  vpFeaturePoint s;
  vpFeaturePoint s_star;
  vpServo servo;
  // Not brace-initialised: ViSP's arrays take a brace list as their elements.
  vpMatrix eJe = vpMatrix(6, 4);
  vpColVector u2 = vpColVector(4);
};

FixationServoVisp::FixationServoVisp(double gain_per_s) : task_(std::make_unique<Task>()) {
  Task& t = *task_;
  t.s.buildFrom(0.0, 0.0, 1.0);
  t.s_star.buildFrom(0.0, 0.0, 1.0);
  t.servo.setServo(vpServo::EYEINHAND_L_cVe_eJe);
  t.servo.setInteractionMatrixType(vpServo::CURRENT, vpServo::PSEUDO_INVERSE);
  t.servo.setLambda(gain_per_s);
  // Identity: Kinematics::jacobian_F already gives the camera's twist in the camera frame.
  t.servo.set_cVe(vpVelocityTwistMatrix());
  t.servo.set_eJe(t.eJe);
  t.servo.addFeature(t.s, t.s_star);
}

FixationServoVisp::~FixationServoVisp() = default;

bool FixationServoVisp::control_law(double x, double y, double Z_m,
                                    const Eigen::Matrix<double, 6, 4>& eJe,
                                    const Eigen::Vector4d& u2, Eigen::Vector4d& u) {
  Task& t = *task_;
  try {
    t.s.buildFrom(x, y, Z_m);
    t.s_star.buildFrom(0.0, 0.0, Z_m);
    for (unsigned r = 0; r < 6; ++r) {
      for (unsigned c = 0; c < 4; ++c) t.eJe[r][c] = eJe(r, c);
    }
    for (unsigned c = 0; c < 4; ++c) t.u2[c] = u2(c);
    t.servo.set_eJe(t.eJe);
    const vpColVector u1 = t.servo.computeControlLaw();
    const vpColVector u_secondary = t.servo.secondaryTask(t.u2);
    for (unsigned c = 0; c < 4; ++c) u(c) = u1[c] + u_secondary[c];
  } catch (...) {  // vpException: a task ViSP cannot serve.
    return false;
  }
  return true;
}

bool FixationServoVisp::interaction(double x, double y, double Z_m,
                                    Eigen::Matrix<double, 2, 6>& L) {
  try {
    vpFeaturePoint point;
    point.buildFrom(x, y, Z_m);
    const vpMatrix L_visp = point.interaction();
    for (unsigned r = 0; r < 2; ++r) {
      for (unsigned c = 0; c < 6; ++c) L(r, c) = L_visp[r][c];
    }
  } catch (...) {
    return false;
  }
  return true;
}

}  // namespace cambio::control::detail
