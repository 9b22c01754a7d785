#pragma once

// The arm loop's law as ViSP's vpServo computes it: the reference detail::ArmReachLaw is held to
// (tests, benchmarks; the cambio_control_visp_reference target of control/CMakeLists.txt, never
// installed). Behind a C++17 interface: ViSP 3.5's headers are not valid C++20 (see
// fixation_servo_visp.hpp), so arm_reach_servo_visp.cpp is compiled as C++17 and this header must
// stay C++17 too.

#include <memory>

#include <Eigen/Core>

namespace cambio::control::detail {

/// Position-based visual servoing of a point: a vpServo (EYEINHAND_L_cVe_eJe, cVe = identity,
/// interaction matrix at the current feature, pseudo-inverse) on one vpFeaturePoint3D, the
/// target seen from a frame T that moves with the fingertips and keeps the base frame's axes,
/// driven to where the fingertips are, and a secondary task in its null space.
///
/// Why this feature: vpFeaturePoint3D's interaction matrix gives p_T' = -v_T - w_T x p_T. T
/// translates with the fingertips but keeps the base's axes (w_T = 0), so its twist is
/// [J_v; 0] q' (J_v the fingertips' linear Jacobian in W) and the law reduces to
/// q' = lambda J_v^+ (target - tip): the error decays exponentially along the straight line to
/// the target, whatever the hand's orientation. The hand's pitch is the arm's one redundant
/// degree of freedom (four joints, three coordinates): the secondary task.
/// Allocates (ViSP's matrices: not for a real-time loop); returns false where ViSP throws.
class ArmReachServoVisp {
 public:
  explicit ArmReachServoVisp(double gain_per_s);
  ~ArmReachServoVisp();
  ArmReachServoVisp(const ArmReachServoVisp&) = delete;
  ArmReachServoVisp& operator=(const ArmReachServoVisp&) = delete;

  /// qdot = lambda J_v^+ e + (I - J_v^+ J_v) u2 for e = target - tip (base frame, m), plus
  /// ViSP's joint-limit avoidance (vpServo::secondaryTaskJointLimitAvoidance, Marey and
  /// Chaumette, ICRA 2010) for joints `q_rad` within 10% of their range of `q_min_rad` or
  /// `q_max_rad`: a joint that nears its limit is turned back within the null space instead of
  /// being clamped there, where the arm would lose a degree of freedom.
  bool control_law(const Eigen::Vector3d& e_W, const Eigen::Matrix<double, 3, 4>& J_v,
                   const Eigen::Vector4d& u2, const Eigen::Vector4d& q_rad,
                   const Eigen::Vector4d& q_min_rad, const Eigen::Vector4d& q_max_rad,
                   Eigen::Vector4d& qdot);

 private:
  struct Task;
  std::unique_ptr<Task> task_;
};

}  // namespace cambio::control::detail
