#include "fixation_law.hpp"

#include <cmath>

namespace cambio::control::detail {

bool FixationLaw::interaction(double x, double y, double Z_m,
                              Eigen::Matrix<double, 2, 6>& L) noexcept {
  if (Z_m < 0 || std::fabs(Z_m) < 1e-6) return false;
  L << -1 / Z_m, 0, x / Z_m, x * y, -(1 + x * x), y,  //
      0, -1 / Z_m, y / Z_m, 1 + y * y, -x * y, -x;
  return true;
}

bool FixationLaw::control_law(double x, double y, double Z_m,
                              const Eigen::Matrix<double, 6, 4>& eJe, const Eigen::Vector4d& u2,
                              Eigen::Vector4d& u) noexcept {
  Eigen::Matrix<double, 2, 6> L;
  if (!interaction(x, y, Z_m, L)) return false;
  const Eigen::Matrix<double, 2, 4> J1 = L * eJe;
  Eigen::Vector4d u1;
  Eigen::Vector4d u_secondary;
  if (!law_.compute(J1, Eigen::Vector2d(x, y), u1) || !law_.secondary_task(u2, u_secondary)) {
    return false;
  }
  u = u1 + u_secondary;
  return u.allFinite();
}

}  // namespace cambio::control::detail
