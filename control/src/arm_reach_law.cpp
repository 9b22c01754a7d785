#include "arm_reach_law.hpp"

namespace cambio::control::detail {

bool ArmReachLaw::control_law(const Eigen::Vector3d& e_W, const Eigen::Matrix<double, 3, 4>& J_v,
                              const Eigen::Vector4d& u2, const Eigen::Vector4d& q_rad,
                              const Eigen::Vector4d& q_min_rad, const Eigen::Vector4d& q_max_rad,
                              Eigen::Vector4d& qdot) noexcept {
  Eigen::Vector4d u1;
  Eigen::Vector4d u_secondary;
  if (!law_.compute(-J_v, e_W, u1) || !law_.secondary_task(u2, u_secondary)) return false;
  const Eigen::Vector4d u = u1 + u_secondary;
  Eigen::Vector4d u_limits;
  law_.joint_limit_avoidance(q_rad, u, q_min_rad, q_max_rad, u_limits);
  qdot = u + u_limits;
  return qdot.allFinite();
}

}  // namespace cambio::control::detail
