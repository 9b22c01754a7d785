#pragma once

// ViSP's visual servoing law in fixed-size Eigen storage: what vpServo computes for the gaze and
// arm servos, without the heap (vpServo's vpMatrix temporaries call malloc about a hundred times
// per law). Private to cambio_control; tests/control/visual_servo_law_visp_test.cpp checks it
// against vpServo itself on random states.

#include <cmath>

#include <Eigen/Core>
#include <Eigen/SVD>

namespace cambio::control::detail {

/// vpServo's law (ViSP 3.5, modules/vs/src/vpServo.cpp) as the gaze and arm servos configure it:
/// EYEINHAND_L_cVe_eJe with cVe = identity, the interaction matrix at the current feature, its
/// PSEUDO_INVERSE at vpServo's default threshold and a constant gain. The caller gives the task
/// Jacobian J1 = L eJe (kFeatures x kJoints) and the error e = s - s*; then
///   compute():               u1 = -lambda W+W J1+ e (vpServo::computeControlLaw), where W+W
///                            projects onto J1's row space (J1's right singular vectors of
///                            singular value above the threshold times the largest);
///   secondary_task():        (I - W+W) de2/dt (vpServo::secondaryTask, the classical projection
///                            operator, Marchand et al. ICRA 2005 eq. 7);
///   joint_limit_avoidance(): vpServo::secondaryTaskJointLimitAvoidance with its default tuning
///                            (Marey and Chaumette, ICRA 2010), on the large projection operator.
/// Written from the published laws (Chaumette and Hutchinson, IEEE RAM 2006; the two papers
/// above) with the defaults and the corner cases ViSP documents for them (see
/// joint_limit_avoidance()), and held to vpServo's results to rounding by the test above.
///
/// Real-time safe: no allocation, no exception (fixed-size matrices, JacobiSVD included). Not
/// thread-safe: compute() keeps J1, e and the projector for the secondary tasks.
template <int kFeatures, int kJoints>
class VisualServoLaw {
 public:
  using TaskJacobian = Eigen::Matrix<double, kFeatures, kJoints>;
  using FeatureVector = Eigen::Matrix<double, kFeatures, 1>;
  using JointVector = Eigen::Matrix<double, kJoints, 1>;
  using JointMatrix = Eigen::Matrix<double, kJoints, kJoints>;

  /// vpServo's m_pseudo_inverse_threshold: singular values at most this times the largest count
  /// as zero (vpMatrix::pseudoInverse).
  static constexpr double kPseudoInverseThreshold = 1e-6;
  /// vpServo::secondaryTaskJointLimitAvoidance's defaults: rho, the fraction of a joint's range
  /// from each limit where avoidance starts; rho1, how far (times rho) beyond that it is at full
  /// strength; lambda_tune, its gain over the primary task's velocity.
  static constexpr double kRho = 0.1;
  static constexpr double kRho1 = 0.3;
  static constexpr double kLambdaTune = 0.7;

  explicit VisualServoLaw(double gain_per_s) : gain_per_s_(gain_per_s) {}

  /// vpServo::computeControlLaw(): u1 = -lambda W+W J1+ e. False (u1 untouched) for a J1 or an e
  /// that is not finite, where vpServo's SVD has no defined result.
  bool compute(const TaskJacobian& J1, const FeatureVector& e, JointVector& u1) noexcept {
    if (!J1.allFinite() || !e.allFinite()) return false;
    J1_ = J1;
    e_ = e;
    svd_.compute(J1, Eigen::ComputeFullU | Eigen::ComputeFullV);
    const auto& sv = svd_.singularValues();
    const auto& U = svd_.matrixU();
    const auto& V = svd_.matrixV();
    // vpMatrix's compute_pseudo_inverse(): the rank against the largest singular value, then
    // J1+ = sum over the rank of v_k u_k^T / sv_k and, for vpServo, W+W = its im(J1^T) times
    // its transpose.
    const double max_sv = sv(0);
    rank_ = 0;
    for (int k = 0; k < sv.size(); ++k) {
      if (sv(k) > max_sv * kPseudoInverseThreshold) ++rank_;
    }
    Eigen::Matrix<double, kJoints, kFeatures> J1p =
        Eigen::Matrix<double, kJoints, kFeatures>::Zero();
    JointMatrix WpW = JointMatrix::Zero();
    for (int k = 0; k < rank_; ++k) {
      J1p.noalias() += V.col(k) * (U.col(k).transpose() / sv(k));
      WpW.noalias() += V.col(k) * V.col(k).transpose();
    }
    JointVector e1;
    if (rank_ == kJoints) {
      // No degree of freedom left: W+W = I.
      e1.noalias() = J1p * e;
      WpW.setIdentity();
    } else {
      e1.noalias() = WpW * (J1p * e);
    }
    u1 = -gain_per_s_ * e1;
    I_WpW_ = JointMatrix::Identity() - WpW;
    return true;
  }

  /// vpServo::secondaryTask(de2dt): (I - W+W) de2dt, after compute(). False where vpServo throws:
  /// a J1 of full column rank leaves no freedom to use.
  bool secondary_task(const JointVector& de2dt, JointVector& out) const noexcept {
    if (rank_ == kJoints) return false;
    out.noalias() = I_WpW_ * de2dt;
    return true;
  }

  /// vpServo::secondaryTaskJointLimitAvoidance(q, dq, q_min, q_max) after compute(), dq the
  /// velocity the avoidance corrects (the primary plus any secondary task). A joint within
  /// kRho of its range from a limit is pushed back along the large projection operator's column
  /// (computeProjectionOperators), smoothly from there and fully from kRho * kRho1 further out,
  /// unless dq outweighs that column there (b >= 1).
  ///
  /// As in ViSP, the per-joint term q2_i and the smoothing factor lambda_l carry over from one
  /// joint to the next: a joint outside its safe range whose b >= 1 adds again the previous
  /// joint's term. That is ViSP 3.5's behaviour, and so this law's.
  void joint_limit_avoidance(const JointVector& q, const JointVector& dq, const JointVector& q_min,
                             const JointVector& q_max, JointVector& q2) const noexcept {
    const JointMatrix P = large_projection_operator();
    JointVector q_l0_min, q_l0_max, q_l1_min, q_l1_max;
    JointVector g = JointVector::Zero();  // The diagonal of ViSP's g.
    for (int i = 0; i < kJoints; ++i) {
      q_l0_min(i) = q_min(i) + kRho * (q_max(i) - q_min(i));
      q_l0_max(i) = q_max(i) - kRho * (q_max(i) - q_min(i));
      q_l1_min(i) = q_l0_min(i) - kRho * kRho1 * (q_max(i) - q_min(i));
      q_l1_max(i) = q_l0_max(i) + kRho * kRho1 * (q_max(i) - q_min(i));
      if (q(i) < q_l0_min(i)) {
        g(i) = -1;
      } else if (q(i) > q_l0_max(i)) {
        g(i) = 1;
      } else {
        g(i) = 0;
      }
    }
    q2.setZero();
    JointVector q2_i = JointVector::Zero();
    double lambda_l = 0.0;
    for (int i = 0; i < kJoints; ++i) {
      if (q(i) > q_l0_min(i) && q(i) < q_l0_max(i)) {
        q2_i = 0 * q2_i;
      } else {
        // P times g's column i, as a product: a non-finite P (e^T J1 = 0) stays so everywhere.
        JointVector g_i = JointVector::Zero();
        g_i(i) = g(i);
        const JointVector Pg_i = P * g_i;
        const double b = std::abs(dq(i)) / std::abs(Pg_i(i));
        if (b < 1.) {
          if (q(i) < q_l1_min(i) || q(i) > q_l1_max(i)) {
            q2_i = -(1 + kLambdaTune) * b * Pg_i;
          } else {
            if (q(i) >= q_l0_max(i) && q(i) <= q_l1_max(i)) {
              lambda_l =
                  1 /
                  (1 + std::exp(-12 * ((q(i) - q_l0_max(i)) / (q_l1_max(i) - q_l0_max(i))) + 6));
            } else if (q(i) >= q_l1_min(i) && q(i) <= q_l0_min(i)) {
              lambda_l =
                  1 /
                  (1 + std::exp(-12 * ((q(i) - q_l0_min(i)) / (q_l1_min(i) - q_l0_min(i))) + 6));
            }
            q2_i = -lambda_l * (1 + kLambdaTune) * b * Pg_i;
          }
        }
      }
      q2 = q2 + q2_i;
    }
  }

  /// The rank of J1 at the last compute().
  int rank() const { return rank_; }

 private:
  /// vpServo::computeProjectionOperators(): between the classical operator I - W+W near the goal
  /// (|e| < 0.1) and the large one I - J1^T e e^T J1 / |e^T J1|^2 far from it (|e| > 0.7), a
  /// sigmoid in between (Marey and Chaumette 2010, eq. 24).
  JointMatrix large_projection_operator() const noexcept {
    constexpr double e0 = 0.1;
    constexpr double e1 = 0.7;
    double sig = 0.0;
    const double norm_e = e_.norm();
    if (norm_e > e1) {
      sig = 1.0;
    } else if (e0 <= norm_e && norm_e <= e1) {
      sig = 1.0 / (1.0 + std::exp(-12.0 * ((norm_e - e0) / ((e1 - e0))) + 6.0));
    } else {
      sig = 0.0;
    }
    const Eigen::Matrix<double, 1, kJoints> eT_J = e_.transpose() * J1_;
    const double pp = eT_J.squaredNorm();
    const JointMatrix P_norm_e = JointMatrix::Identity() - (1.0 / pp) * (eT_J.transpose() * eT_J);
    return sig * P_norm_e + (1 - sig) * I_WpW_;
  }

  double gain_per_s_;
  Eigen::JacobiSVD<TaskJacobian> svd_;
  TaskJacobian J1_ = TaskJacobian::Zero();
  FeatureVector e_ = FeatureVector::Zero();
  JointMatrix I_WpW_ = JointMatrix::Identity();
  int rank_ = 0;
};

}  // namespace cambio::control::detail
