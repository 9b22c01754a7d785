#include "cambio/control/fixation_servo.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>
#include <vector>

#include "fixation_law.hpp"

namespace cambio::control {

namespace {

// solve(): at most this many steps (a converging solve takes about a hundred), and what counts
// as converged: the head has stopped moving and the feature is centred.
constexpr int kMaxSolveSteps = 4000;
constexpr double kSolveStillRad = 1e-10;
constexpr double kSolveCentredNormalized = 1e-6;

bool finite(std::span<const double> values) {
  return std::all_of(values.begin(), values.end(), [](double v) { return std::isfinite(v); });
}

/// The signed amount by which an eye pan lies beyond +-threshold (0 inside).
double beyond(double pan_rad, double threshold_rad) {
  const double over = std::abs(pan_rad) - threshold_rad;
  return over > 0.0 ? std::copysign(over, pan_rad) : 0.0;
}

}  // namespace

struct FixationServo::Impl {
  Impl(const hal::HardwareInfo& hardware, const FixationParams& params_in);

  /// The target in the dominant camera's frame at the kinematics' last update.
  struct Projection {
    Eigen::Vector3d p_C = Eigen::Vector3d::Zero();        ///< As seen.
    Eigen::Vector3d servoed_C = Eigen::Vector3d::Zero();  ///< Within kMaxServoAngleRad.
  };
  bool project(const Eigen::Vector4d& target_W, Projection& out) const;
  FixationError error_of(const Projection& projection) const;
  /// Fills eJe_full from the kinematics' last update.
  bool camera_jacobian();
  hal::Status compute(std::span<const double> q, const Eigen::Vector4d& target_W,
                      double vergence_rad, std::span<double> qdot, FixationError* error,
                      bool scale_to_max_velocity);
  /// The dominant eye pan's range narrowed by the verging eye's at this vergence.
  void servoed_range(double vergence_rad, std::array<double, kServoed>& lo,
                     std::array<double, kServoed>& hi) const;

  Kinematics kinematics;
  HeadJoints head;
  FixationParams params;
  hal::CameraIntrinsics intrinsics;
  int camera = -1;
  std::array<int, kServoed> joints{};
  std::array<hal::JointLimits, kServoed> limits{};
  int verging_pan = -1;
  hal::JointLimits verging_limits;
  double verging_sign = 1.0;  ///< verging pan = dominant pan + verging_sign * vergence.
  double rule_gain_per_s = 0.0;
  std::array<double, kServoed> weights{kNeckWeight, kNeckWeight, 1.0, 1.0};

  Jacobian J_F;
  Eigen::Matrix<double, 6, kServoed> eJe_full;
  std::vector<double> q_solve;
  std::vector<double> qdot_solve;
  detail::FixationLaw law;
};

FixationServo::Impl::Impl(const hal::HardwareInfo& hardware, const FixationParams& params_in)
    : kinematics(hardware),
      head(find_head_joints(kinematics, hardware)),
      params(params_in),
      law(params_in.gain_per_s) {
  const std::string where = "fixation servo on '" + hardware.name + "': ";
  auto positive = [&](double value, const char* name) {
    if (!(value > 0.0) || !std::isfinite(value)) {
      throw std::invalid_argument(where + name + " must be > 0, found " + std::to_string(value));
    }
  };
  positive(params.gain_per_s, "gain_per_s");
  positive(params.neck_rule_rad, "neck_rule_rad");
  positive(params.default_depth_m, "default_depth_m");
  if (params.neck_rule_gain_per_s != 0.0)
    positive(params.neck_rule_gain_per_s, "neck_rule_gain_per_s");
  rule_gain_per_s =
      params.neck_rule_gain_per_s > 0.0 ? params.neck_rule_gain_per_s : params.gain_per_s;

  const hal::Eye dominant = params.dominant_eye;
  const std::string& camera_name =
      dominant == hal::Eye::kLeft ? hardware.stereo->left_camera : hardware.stereo->right_camera;
  intrinsics = hardware.find_camera(camera_name)->intrinsics;
  positive(intrinsics.focal_x_px, "the dominant camera's focal_x_px");
  positive(intrinsics.focal_y_px, "the dominant camera's focal_y_px");
  camera = head.camera(dominant);
  joints = {head.neck_pan, head.neck_tilt, head.eye_tilt, head.pan(dominant)};
  for (int i = 0; i < kServoed; ++i) {
    limits[static_cast<std::size_t>(i)] =
        hardware.joints[static_cast<std::size_t>(joints[static_cast<std::size_t>(i)])].limits;
  }
  verging_pan = head.pan(hal::other(dominant));
  verging_limits = hardware.joints[static_cast<std::size_t>(verging_pan)].limits;
  // vergence = right pan - left pan.
  verging_sign = dominant == hal::Eye::kLeft ? 1.0 : -1.0;

  J_F = kinematics.make_jacobian();
  q_solve.resize(static_cast<std::size_t>(kinematics.joint_count()));
  qdot_solve.resize(q_solve.size());
}

bool FixationServo::Impl::project(const Eigen::Vector4d& target_W, Projection& out) const {
  const Eigen::Isometry3d& X_WC = kinematics.X_WF(camera);
  if (!target_W.allFinite()) return false;
  if (target_W.w() == 0.0) {
    const Eigen::Vector3d d_C = X_WC.linear().transpose() * target_W.head<3>();
    if (d_C.norm() == 0.0) return false;
    out.p_C = d_C.normalized() * params.default_depth_m;
  } else {
    out.p_C = X_WC.inverse() * (target_W.head<3>() / target_W.w());
  }
  const double distance_m = out.p_C.norm();
  if (!(distance_m > 1e-9)) return false;
  out.servoed_C = out.p_C;
  if (out.p_C.z() < std::cos(kMaxServoAngleRad) * distance_m) {
    Eigen::Vector3d lateral(out.p_C.x(), out.p_C.y(), 0.0);
    if (lateral.norm() < 1e-12 * distance_m) lateral = Eigen::Vector3d::UnitX();
    out.servoed_C = distance_m * (std::sin(kMaxServoAngleRad) * lateral.normalized() +
                                  std::cos(kMaxServoAngleRad) * Eigen::Vector3d::UnitZ());
  }
  return true;
}

FixationError FixationServo::Impl::error_of(const Projection& projection) const {
  FixationError error;
  error.in_front = projection.p_C.z() > 0.0;
  const Eigen::Vector3d& p = error.in_front ? projection.p_C : projection.servoed_C;
  error.x = p.x() / p.z();
  error.y = p.y() / p.z();
  error.error_px = std::hypot(intrinsics.focal_x_px * error.x, intrinsics.focal_y_px * error.y);
  return error;
}

bool FixationServo::Impl::camera_jacobian() {
  if (kinematics.jacobian_F(camera, J_F) != hal::Status::kOk) return false;
  for (int c = 0; c < kServoed; ++c) eJe_full.col(c) = J_F.col(joints[static_cast<std::size_t>(c)]);
  return true;
}

void FixationServo::Impl::servoed_range(double vergence_rad, std::array<double, kServoed>& lo,
                                        std::array<double, kServoed>& hi) const {
  for (std::size_t c = 0; c < kServoed; ++c) {
    lo[c] = limits[c].min_position_rad;
    hi[c] = limits[c].max_position_rad;
  }
  const double shift_rad = verging_sign * vergence_rad;
  lo[3] = std::max(lo[3], verging_limits.min_position_rad - shift_rad);
  hi[3] = std::min(hi[3], verging_limits.max_position_rad - shift_rad);
}

hal::Status FixationServo::Impl::compute(std::span<const double> q, const Eigen::Vector4d& target_W,
                                         double vergence_rad, std::span<double> qdot,
                                         FixationError* error, bool scale_to_max_velocity) {
  const auto n = static_cast<std::size_t>(kinematics.joint_count());
  if (qdot.size() == n) std::fill(qdot.begin(), qdot.end(), 0.0);
  if (error != nullptr) *error = FixationError{};
  if (q.size() != n || qdot.size() != n || !finite(q) || !std::isfinite(vergence_rad)) {
    return hal::Status::kRejected;
  }
  Projection projection;
  if (kinematics.update(q) != hal::Status::kOk || !project(target_W, projection) ||
      !camera_jacobian()) {
    return hal::Status::kRejected;
  }
  if (error != nullptr) *error = error_of(projection);

  std::array<double, kServoed> q_servoed{};
  for (std::size_t c = 0; c < kServoed; ++c) q_servoed[c] = q[static_cast<std::size_t>(joints[c])];
  std::array<double, kServoed> lo{};
  std::array<double, kServoed> hi{};
  servoed_range(vergence_rad, lo, hi);

  // The neck rule's request: the neck pan turns towards the side the eyes look at.
  const double dominant_pan_rad = q_servoed[3];
  const double verging_pan_rad = dominant_pan_rad + verging_sign * vergence_rad;
  const double threshold_rad = params.neck_rule_rad - kRuleMarginRad;
  const double excess_rad =
      beyond(dominant_pan_rad, threshold_rad) + beyond(verging_pan_rad, threshold_rad);

  const Eigen::Vector3d& p = projection.servoed_C;
  std::array<double, kServoed> qd{};
  std::array<bool, kServoed> blocked{};
  Eigen::Matrix<double, 6, kServoed> eJe;
  Eigen::Vector4d u2;
  Eigen::Vector4d u;
  // Each pass blocks at least one more joint, or ends.
  for (int pass = 0; pass <= kServoed; ++pass) {
    for (int c = 0; c < kServoed; ++c) {
      const auto k = static_cast<std::size_t>(c);
      eJe.col(c) = blocked[k] ? Eigen::Matrix<double, 6, 1>::Zero().eval()
                              : (eJe_full.col(c) * weights[k]).eval();
    }
    u2.setZero();
    if (!blocked[0]) u2(0) = rule_gain_per_s * excess_rad / weights[0];
    if (!law.control_law(p.x() / p.z(), p.y() / p.z(), p.z(), eJe, u2, u)) {
      return hal::Status::kRejected;
    }
    bool newly_blocked = false;
    for (std::size_t c = 0; c < kServoed; ++c) {
      qd[c] = blocked[c] ? 0.0 : weights[c] * u(static_cast<int>(c));
      const bool at_max = q_servoed[c] >= hi[c] - kAtLimitRad && qd[c] > 0.0;
      const bool at_min = q_servoed[c] <= lo[c] + kAtLimitRad && qd[c] < 0.0;
      if (!blocked[c] && (at_max || at_min)) {
        blocked[c] = true;
        newly_blocked = true;
      }
    }
    if (!newly_blocked) break;
    qd.fill(0.0);
  }

  if (scale_to_max_velocity) {
    double scale = 1.0;
    for (std::size_t c = 0; c < kServoed; ++c) {
      const double max_rad_s = limits[c].max_velocity_rad_s;
      if (max_rad_s > 0.0 && std::abs(qd[c]) * scale > max_rad_s) {
        scale = max_rad_s / std::abs(qd[c]);
      }
    }
    for (double& v : qd) v *= scale;
  }
  for (std::size_t c = 0; c < kServoed; ++c) qdot[static_cast<std::size_t>(joints[c])] = qd[c];
  return hal::Status::kOk;
}

FixationServo::FixationServo(const hal::HardwareInfo& hardware, const FixationParams& params)
    : impl_(std::make_unique<Impl>(hardware, params)) {}
FixationServo::~FixationServo() = default;
FixationServo::FixationServo(FixationServo&&) noexcept = default;
FixationServo& FixationServo::operator=(FixationServo&&) noexcept = default;

hal::Status FixationServo::velocity(std::span<const double> q_tree_rad,
                                    const Eigen::Vector4d& target_W, double vergence_rad,
                                    std::span<double> qdot_tree_rad_s, FixationError* error) {
  return impl_->compute(q_tree_rad, target_W, vergence_rad, qdot_tree_rad_s, error, true);
}

hal::Status FixationServo::solve(std::span<const double> q_start_rad,
                                 const Eigen::Vector4d& target_W, double vergence_rad,
                                 std::span<double> q_out_rad) {
  Impl& m = *impl_;
  const std::size_t n = m.q_solve.size();
  if (q_start_rad.size() != n || q_out_rad.size() != n) return hal::Status::kRejected;
  std::copy(q_start_rad.begin(), q_start_rad.end(), m.q_solve.begin());
  std::array<double, kServoed> lo{};
  std::array<double, kServoed> hi{};
  m.servoed_range(vergence_rad, lo, hi);
  const double step_s = kSolveStepGain / std::max(m.params.gain_per_s, m.rule_gain_per_s);

  FixationError error;
  bool still = false;
  for (int step = 0; step < kMaxSolveSteps && !still; ++step) {
    if (m.compute(m.q_solve, target_W, vergence_rad, m.qdot_solve, &error, false) !=
        hal::Status::kOk) {
      return hal::Status::kRejected;
    }
    double moved_rad = 0.0;
    for (std::size_t c = 0; c < kServoed; ++c) {
      const auto j = static_cast<std::size_t>(m.joints[c]);
      const double before = m.q_solve[j];
      m.q_solve[j] = std::clamp(before + step_s * m.qdot_solve[j], std::min(lo[c], before),
                                std::max(hi[c], before));
      moved_rad = std::max(moved_rad, std::abs(m.q_solve[j] - before));
    }
    still = moved_rad < kSolveStillRad;
  }
  if (!still || !error.in_front || std::hypot(error.x, error.y) > kSolveCentredNormalized) {
    return hal::Status::kRejected;
  }
  const auto dominant = static_cast<std::size_t>(m.joints[3]);
  const auto verging = static_cast<std::size_t>(m.verging_pan);
  m.q_solve[verging] =
      std::clamp(m.q_solve[dominant] + m.verging_sign * vergence_rad,
                 m.verging_limits.min_position_rad, m.verging_limits.max_position_rad);
  std::copy(m.q_solve.begin(), m.q_solve.end(), q_out_rad.begin());
  return hal::Status::kOk;
}

Eigen::Vector3d FixationServo::pixel_ray_W(std::span<const double> q_tree_rad, double u_px,
                                           double v_px) {
  Impl& m = *impl_;
  if (m.kinematics.update(q_tree_rad) != hal::Status::kOk) {
    return Eigen::Vector3d::Constant(std::numeric_limits<double>::quiet_NaN());
  }
  const Eigen::Vector3d d_C((u_px - m.intrinsics.principal_x_px) / m.intrinsics.focal_x_px,
                            (v_px - m.intrinsics.principal_y_px) / m.intrinsics.focal_y_px, 1.0);
  return m.kinematics.X_WF(m.camera).linear() * d_C.normalized();
}

FixationError FixationServo::error(std::span<const double> q_tree_rad,
                                   const Eigen::Vector4d& target_W) {
  Impl& m = *impl_;
  Impl::Projection projection;
  if (m.kinematics.update(q_tree_rad) != hal::Status::kOk || !m.project(target_W, projection)) {
    return {};
  }
  return m.error_of(projection);
}

hal::Status FixationServo::feature_jacobian(std::span<const double> q_tree_rad,
                                            const Eigen::Vector4d& target_W,
                                            Eigen::Matrix<double, 2, kServoed>& J) {
  Impl& m = *impl_;
  Impl::Projection projection;
  if (m.kinematics.update(q_tree_rad) != hal::Status::kOk || !m.project(target_W, projection) ||
      !m.camera_jacobian()) {
    return hal::Status::kRejected;
  }
  const Eigen::Vector3d& p = projection.servoed_C;
  Eigen::Matrix<double, 2, 6> L;
  if (!detail::FixationLaw::interaction(p.x() / p.z(), p.y() / p.z(), p.z(), L)) {
    return hal::Status::kRejected;
  }
  J = L * m.eJe_full;
  return hal::Status::kOk;
}

const std::array<int, FixationServo::kServoed>& FixationServo::servoed_joints() const {
  return impl_->joints;
}
int FixationServo::verging_pan() const {
  return impl_->verging_pan;
}
const FixationParams& FixationServo::params() const {
  return impl_->params;
}
const Kinematics& FixationServo::kinematics() const {
  return impl_->kinematics;
}
const HeadJoints& FixationServo::head() const {
  return impl_->head;
}

}  // namespace cambio::control
