#pragma once

// FixationServo's control law: ViSP's vpServo task of fixation_servo_visp.hpp, computed by
// VisualServoLaw without the heap. Private to cambio_control.

#include <Eigen/Core>

#include "visual_servo_law.hpp"

namespace cambio::control::detail {

/// vpServo (EYEINHAND_L_cVe_eJe, cVe = identity, interaction matrix at the current feature,
/// pseudo-inverse) on one vpFeaturePoint s = (x, y) driven to s* = (0, 0), with a secondary task
/// in its null space: FixationServoVisp's law, to rounding, with no allocation and no exception.
class FixationLaw {
 public:
  explicit FixationLaw(double gain_per_s) : law_(gain_per_s) {}

  /// u = -lambda (L eJe)^+ e + (I - (L eJe)^+ (L eJe)) u2 (vpServo::computeControlLaw and
  /// vpServo::secondaryTask) for the point at normalized (x, y), depth Z_m. False where vpServo
  /// throws (interaction()) or for values that are not finite. Real-time safe.
  bool control_law(double x, double y, double Z_m, const Eigen::Matrix<double, 6, 4>& eJe,
                   const Eigen::Vector4d& u2, Eigen::Vector4d& u) noexcept;

  /// vpFeaturePoint::interaction(): the point's interaction matrix (Chaumette and Hutchinson,
  /// "Visual servo control, Part I", IEEE RAM 2006, eq. 11) in the camera frame. False, as
  /// vpFeaturePoint throws, for a point behind the camera or within 1e-6 m of its plane.
  static bool interaction(double x, double y, double Z_m, Eigen::Matrix<double, 2, 6>& L) noexcept;

 private:
  VisualServoLaw<2, 4> law_;
};

}  // namespace cambio::control::detail
