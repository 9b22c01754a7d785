#pragma once

// The arm servo's control law: ViSP's vpServo task of arm_reach_servo_visp.hpp, computed by
// VisualServoLaw without the heap. Private to cambio_control.

#include <Eigen/Core>

#include "visual_servo_law.hpp"

namespace cambio::control::detail {

/// Position-based servoing of the fingertips to a point: ArmReachServoVisp's law (see its header
/// for the feature and why it reduces to this), to rounding, with no allocation and no exception.
/// vpFeaturePoint3D's interaction matrix of the target seen from a frame T that translates with
/// the fingertips and keeps the base's axes, times T's Jacobian [J_v; 0], is -J_v whatever the
/// point, so the task Jacobian is J1 = -J_v and the error s - s* = target - tip.
class ArmReachLaw {
 public:
  explicit ArmReachLaw(double gain_per_s) : law_(gain_per_s) {}

  /// qdot = lambda J_v^+ e + (I - J_v^+ J_v) u2 for e = target - tip (base frame, m), plus
  /// vpServo::secondaryTaskJointLimitAvoidance for joints `q_rad` within 10% of their range of
  /// `q_min_rad` or `q_max_rad` (VisualServoLaw::joint_limit_avoidance). False for values that
  /// are not finite. Real-time safe.
  bool control_law(const Eigen::Vector3d& e_W, const Eigen::Matrix<double, 3, 4>& J_v,
                   const Eigen::Vector4d& u2, const Eigen::Vector4d& q_rad,
                   const Eigen::Vector4d& q_min_rad, const Eigen::Vector4d& q_max_rad,
                   Eigen::Vector4d& qdot) noexcept;

 private:
  VisualServoLaw<3, 4> law_;
};

}  // namespace cambio::control::detail
