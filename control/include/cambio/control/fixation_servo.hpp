#pragma once

#include <array>
#include <memory>
#include <numbers>
#include <span>

#include <Eigen/Core>

#include "cambio/control/head_joints.hpp"
#include "cambio/control/kinematics.hpp"
#include "cambio/hal/eye.hpp"
#include "cambio/hal/hardware_info.hpp"
#include "cambio/hal/status.hpp"

namespace cambio::control {

/// The servo's settings. No tuning defaults: the zeros are refused by the constructor, so a field
/// left unset cannot pass (the experiment file gives them, as for VergenceParams).
struct FixationParams {
  hal::Eye dominant_eye = hal::Eye::kLeft;
  double gain_per_s = 0.0;       ///< IBVS lambda (> 0): the feature error decays as e^(-lambda t).
  double neck_rule_rad = 0.0;    ///< The paper's 30°: largest eye pan (either eye) at rest (> 0).
  double default_depth_m = 0.0;  ///< Depth of a target given as a direction (> 0).
  /// Rate at which an eye pan beyond the rule is brought back by turning the neck (1/s); 0 takes
  /// gain_per_s.
  double neck_rule_gain_per_s = 0.0;
};

/// Where the target is in the dominant eye's image.
struct FixationError {
  double x = 0.0;  ///< Normalized image coordinates (X/Z, Y/Z; OpenCV optical frame).
  double y = 0.0;
  double error_px = 0.0;  ///< |(fx x, fy y)|: pixels from the principal point.
  /// False for a target behind the camera (z <= 0): x, y then give the direction the servo
  /// turns to (see FixationServo), not a projection.
  bool in_front = false;
};

/// Fixation of a target by the dominant eye with ViSP's vpServo law: an image-based point feature
/// driven to the image centre over the head's neck pan, neck tilt, eye tilt and dominant eye pan
/// ("the servoed joints", in that order in every 4-vector below). The law is vpServo's, computed
/// in fixed-size Eigen storage (control/src/visual_servo_law.hpp) so that it never allocates;
/// tests/control/visual_servo_law_visp_test.cpp holds it to vpServo's own on random states.
///
/// The law (vpServo::EYEINHAND_L_cVe_eJe, interaction matrix at the current feature): s = (x, y)
/// the target projected through the believed kinematics into the dominant camera's optical
/// frame, s* = (0, 0), e = s - s*, eJe = Kinematics::jacobian_F(camera) restricted to the
/// servoed joints (its twist is already in the camera frame, so cVe = identity), and
///   q_dot = D (u1 + P u2),  u1 = -lambda (L eJe D)^+ e,  P = I - (L eJe D)^+ (L eJe D)
/// i.e. a weighted least-norm law (vpServo sees eJe D) plus a secondary task in its null space
/// (vpServo::secondaryTask).
///
/// Weights D = diag(kNeckWeight, kNeckWeight, 1, 1): the least-norm solution in u = D^-1 q_dot
/// shares the motion between joints of similar effect in proportion to the squared weights, so
/// with kNeckWeight = 0.1 the neck does about 1 % of a gaze shift and the eyes the rest (the
/// paper: the eyes move while they stay within 30°). A hard switch (neck column off inside the
/// rule) would also work but makes the law discontinuous at the rule's edge.
///
/// The 30° neck rule is the secondary task, chosen over ViSP's joint-limit-avoidance task: that
/// task asks for an eye pan velocity, and in the weighted null space an eye can only come back
/// if the neck (weight 0.1) turns, so its effect shrinks by kNeckWeight^2. Instead the secondary
/// task asks the neck pan to turn towards the side the eyes look at, at neck_rule_gain_per_s
/// times how far the eye pans (the dominant one, and the verging one at dominant ± vergence) are
/// beyond the rule: projected into the primary task's null space the neck turns, the dominant eye
/// counter-rotates by the same angle and the feature stays put. It acts from
/// neck_rule_rad - kRuleMarginRad, so the eyes settle strictly inside the rule, not
/// exponentially close to it from outside.
///
/// Limits (hal::JointLimits of each servoed joint; for the dominant eye pan also the verging
/// eye's limits shifted by the vergence): a joint at a limit (within kAtLimitRad, or beyond it)
/// whose velocity would push it further is removed from the law (its column zeroed) and the law
/// solved again, so the other joints take its share: no wind-up. Integrating q_dot is the
/// caller's, who clamps positions to the limits (the joint loop does). Finally q_dot is scaled
/// down uniformly, keeping its direction, until no joint exceeds its max velocity.
///
/// A target more than kMaxServoAngleRad off the optical axis (or behind the camera) is servoed
/// towards the point at that angle in the same direction, so the error stays bounded and points
/// the right way. Lens distortion is ignored (the pinhole intrinsics only): the sim has none,
/// and a real lens's is small at the image centre where fixation ends.
///
/// Lifecycle: the constructor allocates and may throw; velocity(), solve(), feature_jacobian(),
/// pixel_ray_W() and error() are real-time safe: no allocation, no exception; they return
/// kRejected for wrong sizes or a target at the camera centre. Cost on the shipped rig
/// (bench/fixation_servo_bench): velocity() about 2 us, solve() about 0.2 ms. Not thread-safe:
/// one loop owns an instance.
class FixationServo {
 public:
  static constexpr int kServoed = 4;
  static constexpr double kNeckWeight = 0.1;
  static constexpr double kRuleMarginRad = 0.5 * std::numbers::pi / 180.0;
  static constexpr double kAtLimitRad = 1e-6;
  static constexpr double kMaxServoAngleRad = 70.0 * std::numbers::pi / 180.0;

  /// Throws std::invalid_argument for a parameter out of range, a rig without the head
  /// (find_head_joints()) or a dominant camera without a focal length.
  FixationServo(const hal::HardwareInfo& hardware, const FixationParams& params);
  ~FixationServo();
  FixationServo(FixationServo&&) noexcept;
  FixationServo& operator=(FixationServo&&) noexcept;

  /// The fixation law at believed positions q_tree_rad (tree order, size joint_count()) for
  /// target_W (homogeneous: w = 0 is a direction, taken at default_depth_m). vergence_rad as in
  /// the gaze plan: the verging eye's pan = dominant ± vergence (right = left + vergence); the
  /// neck rule and the dominant eye's limits account for it. Writes qdot_tree_rad_s (tree order;
  /// zero for every joint but the four servoed). kRejected leaves qdot zero.
  [[nodiscard]] hal::Status velocity(std::span<const double> q_tree_rad,
                                     const Eigen::Vector4d& target_W, double vergence_rad,
                                     std::span<double> qdot_tree_rad_s,
                                     FixationError* error = nullptr);

  /// The head pose that fixates target_W with the neck rule satisfied, from q_start_rad: the law
  /// iterated on the model (no max-velocity scaling, steps of kSolveStepGain / gain) until it
  /// stops moving: the end point of a saccade. q_out_rad is q_start_rad with the servoed joints
  /// replaced and the verging eye's pan set to dominant ± vergence (within its limits).
  /// kRejected if it does not converge to a centred feature (unreachable within the limits).
  [[nodiscard]] hal::Status solve(std::span<const double> q_start_rad,
                                  const Eigen::Vector4d& target_W, double vergence_rad,
                                  std::span<double> q_out_rad);

  /// Unit ray through pixel (u right, v down) of the dominant camera at q, in W (pinhole, no
  /// distortion). NaN for a q of the wrong size.
  Eigen::Vector3d pixel_ray_W(std::span<const double> q_tree_rad, double u_px, double v_px);
  /// Where target_W is in the dominant eye's image at q (all zero for a q of the wrong size).
  FixationError error(std::span<const double> q_tree_rad, const Eigen::Vector4d& target_W);

  /// d(x, y)/d(servoed joints) at q: the point's interaction matrix (vpFeaturePoint's) times
  /// eJe, unweighted.
  [[nodiscard]] hal::Status feature_jacobian(std::span<const double> q_tree_rad,
                                             const Eigen::Vector4d& target_W,
                                             Eigen::Matrix<double, 2, kServoed>& J);

  /// Tree indices of neck pan, neck tilt, eye tilt, dominant eye pan.
  const std::array<int, kServoed>& servoed_joints() const;
  /// The verging (non-dominant) eye's pan joint.
  int verging_pan() const;
  const FixationParams& params() const;
  const Kinematics& kinematics() const;
  const HeadJoints& head() const;

  /// solve()'s Euler step times gain: each step removes this fraction of the error.
  static constexpr double kSolveStepGain = 0.25;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace cambio::control
