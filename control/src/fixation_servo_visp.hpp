#pragma once

// FixationServo's law as ViSP's vpServo computes it: the reference detail::FixationLaw is held to
// (tests, benchmarks; the cambio_control_visp_reference target of control/CMakeLists.txt, never
// installed). Behind a C++17 interface: ViSP 3.5's headers are not valid C++20 (vpArray2D
// declares constructors as template-ids, ill-formed since CWG 2237, an error in GCC 12), so
// fixation_servo_visp.cpp is compiled as C++17 and this header must stay C++17 too.

#include <memory>

#include <Eigen/Core>

namespace cambio::control::detail {

/// A vpServo (EYEINHAND_L_cVe_eJe, cVe = identity, interaction matrix at the current feature,
/// pseudo-inverse) on one vpFeaturePoint driven to (0, 0), with a secondary task in its null
/// space. Allocates (ViSP's matrices: not for a real-time loop); returns false where ViSP throws.
class FixationServoVisp {
 public:
  explicit FixationServoVisp(double gain_per_s);
  ~FixationServoVisp();
  FixationServoVisp(const FixationServoVisp&) = delete;
  FixationServoVisp& operator=(const FixationServoVisp&) = delete;

  /// u = -lambda (L eJe)^+ e + (I - (L eJe)^+ (L eJe)) u2 (vpServo::computeControlLaw and
  /// vpServo::secondaryTask) for the point at normalized (x, y), depth Z_m.
  bool control_law(double x, double y, double Z_m, const Eigen::Matrix<double, 6, 4>& eJe,
                   const Eigen::Vector4d& u2, Eigen::Vector4d& u);

  /// ViSP's interaction matrix of the point (vpFeaturePoint::interaction()).
  static bool interaction(double x, double y, double Z_m, Eigen::Matrix<double, 2, 6>& L);

 private:
  struct Task;
  std::unique_ptr<Task> task_;
};

}  // namespace cambio::control::detail
