#pragma once

#include <array>
#include <memory>
#include <numbers>
#include <optional>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "cambio/control/believed_joints.hpp"
#include "cambio/control/command_tracking.hpp"
#include "cambio/control/fixation_servo.hpp"
#include "cambio/control/gaze_command.hpp"
#include "cambio/control/head_joints.hpp"
#include "cambio/control/joint_frames.hpp"
#include "cambio/control/joint_trajectory_follower.hpp"
#include "cambio/control/kinematics.hpp"
#include "cambio/control/pursuit_tracker.hpp"
#include "cambio/control/saccade_profile.hpp"
#include "cambio/control/trajectory_inbox.hpp"
#include "cambio/control/vergence_controller.hpp"
#include "cambio/hal/hardware_info.hpp"
#include "cambio/hal/loop.hpp"
#include "cambio/hal/seqlock_channel.hpp"
#include "cambio/perception/sensory_servo.hpp"
#include "cambio/perception/ssm_server.hpp"

namespace cambio::control {

/// Settings of the gaze loop. No tuning defaults here: the experiment file's loader holds them.
struct GazeLoopParams {
  /// Dominant eye, fixation gain, the neck rule, default depth (FixationServo).
  FixationParams fixation;
  /// The verging eye (the other one), its focal length, gain, confidence floor, largest step.
  VergenceParams vergence;
  bool vergence_enabled = true;
  /// At a saccade to a 3-D point (not a pixel or a direction, whose depth is a guess), set the
  /// vergence its geometry needs instead of keeping it; vision refines it after the saccade.
  bool predictive_vergence = false;
  /// Pursuit: the servo's gain while pursuing (1/s), and how far ahead the target is
  /// extrapolated, as a fraction of the law's time constant 1/gain (1: a target moving at constant
  /// angular velocity is followed without lag; 0: no lead).
  double pursuit_gain_per_s = 0.0;
  double pursuit_lead = 0.0;
  /// Time constant of the pursued target's angular velocity filter (s): about one frame at
  /// 30 Hz. Positions come from the displacement since a key frame, precise enough that the
  /// velocity needs little smoothing; a longer filter makes the eye trail a target that sets off
  /// fast (0.1 s: pursuit on generated scenes 79 -> 75 of 100, median RMS 0.36 -> 0.48 deg).
  double pursuit_velocity_filter_s = 0.03;
  /// How far each head joint's command may lead its measured position before the loop faults
  /// (CommandTracking), one per hardware.joints entry (rad); empty: unbounded.
  std::vector<double> max_tracking_error_rad;
};

/// The head's control loop (the paper's Control Module for gaze), at the control rate:
///  - fixation: the dominant eye brings a target to its image centre with ViSP's vpServo law over
///    the neck and eye joints, the 30° neck rule as its redundancy (FixationServo); the servo runs
///    on the commanded pose (the robot's intent, the kinematics' camera Jacobian at it), so the
///    servo's own dynamics do not fight the drives' lag;
///  - vergence: the other eye's pan is the dominant eye's plus a vergence angle that each new
///    confident disparity measurement corrects (VergenceController). The angle is kept within
///    [0, what the verging eye's joint limits allow], so the eyes never diverge — at start, on low
///    confidence, whatever is measured — and nothing winds up at a limit; the neck rule sees the
///    verging eye too;
///  - saccades: a jump to the servo's end pose for a new target along a synchronised
///    velocity- and acceleration-limited profile (SaccadeProfile); the verging eye moves
///    conjugately (same vergence) and re-verges once the dominant eye stops;
///  - smooth pursuit: the target's direction from the SSM's motion estimate (PursuitTracker),
///    extrapolated ahead by the servo's lag;
///  - it asks the SSM for what it needs (the SSM's request channel): disparity always (vergence,
///    reports), motion only while pursuing.
/// Joints outside the head hold their initial pose, or follow the overlay (set_overlay()). The
/// loop publishes targets for every rig joint and a GazeStatus each cycle.
///
/// The drives not following (CommandTracking): while a joint loop holds or a head joint is not
/// driven the loop freezes (commands are taken, nothing moves: no servo, no saccade time, no
/// vergence correction); on the first cycle they follow again it publishes the measured pose
/// and restarts from it (a saccade is planned again from there to its target). A head joint
/// whose command leads its measurement by more than its max_tracking_error_rad is a fault of
/// this loop: it reports it (hal::Loop::fault_message), holds where the joints are, refuses
/// every later motion (GazeRefusal::kTrackingFault) and returns kFault to the end of the run.
/// A joint move (kMoveJoint) goes at the joint's velocity limit. A joint trajectory (from the
/// trajectory channel, set_trajectories()) moves the head joints it names along it from where
/// they are commanded, the others held, no servo and no vergence correction meanwhile; then the
/// head holds its last point. A later command or trajectory replaces it; a hold of the drives
/// ends it where the joints are (its timing is gone). Joints that are not the head's refuse it.
///
/// Real-time: everything is allocated at construction; update() never allocates.
class GazeLoop final : public hal::Loop {
 public:
  /// `rig_joint_order`: the rig's joints in rig order (JointTargetFrame order); `pose` every
  /// joint's initial target in that order. Throws std::invalid_argument on a rig without a
  /// stereo head or inconsistent settings.
  GazeLoop(const hal::HardwareInfo& hardware, const GazeLoopParams& params,
           const JointTargetFrame& pose, BelievedJoints believed,
           const hal::SeqlockChannel<perception::SsmSummary>& summaries,
           hal::SeqlockChannel<perception::SsmRequest>& ssm_requests,
           const hal::SeqlockChannel<GazeCommand>& commands,
           hal::SeqlockChannel<JointTargetFrame>& targets);
  ~GazeLoop() override;

  const std::string& name() const override { return name_; }
  void activate() override;
  hal::Status update(const hal::LoopTick& tick) noexcept override;

  const hal::SeqlockChannel<GazeStatus>& status() const { return status_channel_; }
  /// Features the decision layer (a console, a behaviour) wants from the SSM besides what the
  /// gaze needs: the loop asks for both. Set before the run (configure time); null: none.
  void set_extra_features(const hal::SeqlockChannel<perception::FeatureRequest>* extra) {
    extra_features_channel_ = extra;
  }

  /// The channel of joint trajectories for the head (configure time; null: none).
  void set_trajectories(const hal::SeqlockChannel<JointTrajectory>* trajectories) {
    trajectories_.set_channel(trajectories);
  }
  /// Trajectories started, and those that reached their last point.
  const JointTrajectoryFollower& trajectory_follower() const { return follower_; }

  /// Joints another loop commands (the arms, ArmReachLoop): at each publish the gaze loop copies
  /// the commands of `rig_indices` from the newest frame of `overlay` (rig order, every joint)
  /// into its own, keeping its own until one arrives. Configure time, before the executor runs
  /// (allocates); throws std::invalid_argument for an index outside the rig or a head joint.
  void set_overlay(const hal::SeqlockChannel<JointTargetFrame>* overlay,
                   std::vector<int> rig_indices);
  /// Commands that could not be carried out (a target behind the eye, an unsolvable saccade).
  std::uint64_t rejected_commands() const { return rejected_commands_; }
  std::uint64_t corrections() const { return corrections_; }
  std::uint64_t measurements() const { return measurements_; }
  /// Large disparity jumps held back, once verged, until a second measurement confirmed them.
  std::uint64_t held_jumps() const { return held_jumps_; }
  /// Large disparity jumps rejected, once verged, because the dominant eye's fovea still showed
  /// the same surface: something passed between the verging eye and the target.
  std::uint64_t occlusion_rejections() const { return occlusion_rejections_; }
  /// Anchors forgotten because a confident jump was confirmed while neither eye's fovea had
  /// changed since the anchor was last verged on: nothing can have come in front of the verging
  /// eye, so the anchor was a false match (a periodic texture's alias).
  std::uint64_t false_anchors() const { return false_anchors_; }
  /// Returns to the anchored vergence (the last one verged on the current target) when a
  /// measurement asked for it again after the verging eye had been drawn off.
  std::uint64_t anchor_returns() const { return anchor_returns_; }
  /// Anchors moved to a vergence far from the old one, after the eye had held it
  /// kReanchorAfter_s (the fixated object really changed depth, or a false anchor was left).
  std::uint64_t reanchors() const { return reanchors_; }
  /// Measurements not followed, once verged on an anchor, because they asked to leave it (by
  /// more than kAnchorAgreementRad) with much less confidence than the readings that verified
  /// it (below kDepartureConfidenceShare of theirs): an object coming into the window's edge.
  std::uint64_t doubtful_departures() const { return doubtful_departures_; }
  /// Vergence steps taken on kFaintAgreements faint readings in a row (before anything was verged
  /// on since the command).
  std::uint64_t faint_steps() const { return faint_steps_; }
  /// Pursuit frames whose motion was measured one way only and completed by the fixated
  /// object's region (PursuitTracker::region_frames).
  std::uint64_t pursuit_region_frames() const { return pursuit_.region_frames(); }
  /// The head joints' tracking: frozen cycles, restarts, the largest lead, a fault. Read it from
  /// the loop's thread or after the executor stopped.
  const CommandTracking& tracking() const { return tracking_; }

  /// Once the vergence error has been below kVergedRad, an error above kVergenceJumpRad needs a
  /// second measurement to confirm it (see verge()).
  static constexpr double kVergedRad = 0.25 * std::numbers::pi / 180.0;
  static constexpr double kVergenceJumpRad = 1.0 * std::numbers::pi / 180.0;
  /// Point targets farther than this (all directions alike for a 12 cm baseline) or nearer than
  /// kMinTargetDistance_m (no direction) are refused.
  static constexpr double kMaxTargetDistance_m = 1000.0;
  static constexpr double kMinTargetDistance_m = 0.01;
  /// Two weak measurements agree within this (plus a tenth of the error): about 2 px at 554 px.
  static constexpr double kWeakAgreementRad = 0.2 * std::numbers::pi / 180.0;
  /// Before anything has been verged on since the command (or near the anchor, within
  /// kAnchorAgreementRad), a reading too faint to count (below a third of min_confidence) is
  /// followed once this many in a row agree (kWeakAgreementRad):
  /// a large true disparity, or a periodic texture's, scores little margin over its aliases
  /// frame after frame, and ignoring it leaves the eyes parallel for good; a step towards it
  /// brings the target to disparities the fovea's levels match confidently, or shows it wrong.
  static constexpr int kFaintAgreements = 4;
  /// The dominant fovea shows the same surface as a frame ago when it moved less than this and
  /// the previous frame, moved, matches it to this rms (grey levels: a few times sensor noise).
  static constexpr double kSteadyFlowPx = 1.0;
  /// A measurement asks for the anchored vergence when within this of it (about 3 px).
  static constexpr double kAnchorAgreementRad = 0.3 * std::numbers::pi / 180.0;
  static constexpr double kSteadyResidualGrey = 3.0;
  /// A vergence more than kVergenceJumpRad from the anchor becomes the anchor only once the eye
  /// has stayed verged near it this long: longer than a distractor takes to cross the view.
  static constexpr double kReanchorAfter_s = 0.5;
  /// A confirmed jump away from the anchor while the dominant fovea's view changes (an object
  /// crossing in front of the target, or the target's own motion) is believed only once it has
  /// lasted this long: about as long as an object takes to cross the fovea, so a passing one
  /// never draws the verging eye off (each reading held counts in held_jumps()).
  static constexpr double kJumpFromAnchorAfter_s = 0.25;
  /// A reading asking to leave the anchor needs this share of the anchor's own confidence.
  static constexpr double kDepartureConfidenceShare = 0.75;
  /// The anchor's confidence keeps this share of its previous value per verifying reading when a
  /// weaker one verifies it (about a quarter-second memory at 30 frames a second).
  static constexpr double kAnchorConfidenceHold = 0.9;

 private:
  enum class Mode : std::uint8_t { kHold, kFixate, kSaccade, kPursue, kTrajectory };
  struct CameraPoseSample {
    std::int64_t stamp_ns = 0;
    Eigen::Matrix3d R_WC = Eigen::Matrix3d::Identity();
  };

  void apply(const GazeCommand& command, std::int64_t now_ns) noexcept;
  /// A new trajectory from the channel: started, or refused for a joint that is not the head's.
  void start_trajectory(std::int64_t now_ns) noexcept;
  /// The head's command set to the measured pose after the joints held; a saccade in progress
  /// is planned again from there.
  void restart_from_measured(std::int64_t now_ns) noexcept;
  /// A kMoveJoint in progress: one step toward its goal at the joint's velocity limit.
  void step_move(double dt_s) noexcept;
  /// The head's command where the joints are, every motion stopped: a tracking fault.
  void stop_on_tracking_fault() noexcept;
  /// The vergence the commanded eye pans make (>= 0 converged, as vergence_rad_ counts it).
  double commanded_vergence_rad() const noexcept;
  void write_targets(std::int64_t now_ns) noexcept;
  /// Whether the dominant eye's fovea shows the surface it showed a frame ago (its motion
  /// estimate: small flow, small residual at the finest level).
  /// Verged at vergence_rad_ (a measurement's error below kVergedRad): moves the anchor there if
  /// it is near, or once the eye has stayed there kReanchorAfter_s.
  void anchor_on(std::int64_t stamp_ns, double confidence) noexcept;
  /// Whether a faint reading (below a third of min_confidence) is the kFaintAgreements-th in a
  /// row to agree, before anything has been verged on or near the anchor: then it is followed.
  bool faint_reading_persists(double error_rad, double asked_rad) noexcept;
  /// Whether a reading agrees with an earlier one (kWeakAgreementRad plus a tenth of the error),
  /// as it stood or less the vergence applied since.
  static bool readings_agree(double error_rad, double earlier_error_rad,
                             double applied_since_rad) noexcept;
  bool dominant_fovea_steady(const perception::SsmSummary& summary) const noexcept;
  /// Whether the verging eye's fovea may show new content since the previous frame: its motion
  /// not tracked to the finest level, or the previous frame, moved, not matching it. Its flow is
  /// not asked to be small, since the vergence steps themselves turn that eye.
  bool verging_fovea_changed(const perception::SsmSummary& summary) const noexcept;
  bool resolve(const GazeTarget& target, Eigen::Vector4d& target_W) const noexcept;
  /// Moves a head joint's commanded position (clamped to its limits); false for a joint that is
  /// not the head's or a position that is not finite.
  bool move_joint(int rig_index, double position_rad) noexcept;
  bool is_head_joint(int tree_index) const noexcept;
  void start_saccade(std::int64_t now_ns) noexcept;
  /// Counts a command not carried out and says why (GazeStatus::last_refusal).
  void refuse(GazeRefusal why) noexcept;
  void servo_step(double gain_scale, double dt_s) noexcept;
  void verge(const perception::SsmSummary& summary) noexcept;
  void clamp_vergence() noexcept;
  void place_verging_eye() noexcept;
  double depth_estimate_m() const noexcept;
  const Eigen::Matrix3d& R_WC_at(std::int64_t stamp_ns) const noexcept;
  void update_belief(std::int64_t now_ns) noexcept;
  void publish(std::int64_t now_ns) noexcept;
  void request_features() noexcept;
  /// The fixated object's region is computed while the eyes fixate (pursuit starts from the
  /// last one) and pursue, or when another consumer asked for it.
  bool wants_region() const noexcept {
    return extra_features_.region || mode_ == Mode::kFixate || mode_ == Mode::kPursue;
  }

  std::string name_ = "control";
  GazeLoopParams params_;
  hal::Eye dominant_;
  hal::Eye verging_;
  std::unique_ptr<FixationServo> servo_;
  HeadJoints head_;
  CommandTracking tracking_;
  Kinematics believed_kinematics_;
  VergenceController vergence_controller_;
  PursuitTracker pursuit_;
  SaccadeProfile saccade_;
  std::vector<hal::JointLimits> limits_tree_;
  std::vector<int> rig_to_tree_;

  BelievedJoints believed_;
  const hal::SeqlockChannel<perception::SsmSummary>& summaries_;
  hal::SeqlockChannel<perception::SsmRequest>& ssm_requests_;
  const hal::SeqlockChannel<GazeCommand>& commands_;
  hal::SeqlockChannel<JointTargetFrame>& targets_;
  hal::SeqlockChannel<GazeStatus> status_channel_;
  TrajectoryInbox trajectories_;
  JointTrajectoryFollower follower_;
  const hal::SeqlockChannel<JointTargetFrame>* overlay_ = nullptr;
  std::vector<int> overlay_rig_indices_;
  JointTargetFrame overlay_frame_{};

  JointTargetFrame pose_;                // Rig order: what is commanded.
  std::vector<double> q_command_tree_;   // The commanded pose, tree order.
  std::vector<double> q_believed_rig_;   // Encoders, rig order.
  std::vector<double> q_believed_tree_;  // Encoders, tree order.
  std::vector<double> qdot_tree_;        // Servo output, tree order.
  std::vector<double> q_scratch_tree_;   // Saccade end pose.
  std::array<int, 5> saccade_joints_{};  // Neck pan, neck tilt, eye tilt, dominant, verging.
  std::array<double, 5> saccade_q0_{}, saccade_q1_{}, saccade_vmax_{}, saccade_amax_{};
  std::array<double, 5> saccade_q_{}, saccade_qdot_{};
  std::int64_t saccade_start_ns_ = 0;
  double saccade_end_vergence_rad_ = 0.0;
  /// Images exposed before this time (the end of the last saccade) saw the eyes moving fast:
  /// their disparities belong to no pose the loop can correct from, and are not used.
  std::int64_t vergence_blind_until_ns_ = 0;

  std::array<CameraPoseSample, 64> camera_poses_{};  // Believed dominant orientation history.
  std::size_t camera_pose_next_ = 0;

  Mode mode_ = Mode::kHold;
  bool verge_ = false;
  bool target_set_ = false;
  int move_joint_ = -1;  // Tree index of a kMoveJoint in progress.
  double move_goal_rad_ = 0.0;
  Eigen::Vector4d target_W_ = Eigen::Vector4d(1.0, 0.0, 0.0, 0.0);
  double pursuit_depth_m_ = 1.0;
  double vergence_rad_ = 0.0;

  GazeCommand command_{};
  std::uint64_t last_command_sequence_ = 0;
  perception::SsmSummary summary_{};
  std::uint64_t last_summary_sequence_ = 0;
  perception::SsmRequest request_{};
  const hal::SeqlockChannel<perception::FeatureRequest>* extra_features_channel_ = nullptr;
  perception::FeatureRequest extra_features_{
      .maps = 0, .disparity = false, .motion = false, .moments = false};
  GazeStatus status_{};
  FixationError fixation_error_{};
  std::uint64_t rejected_commands_ = 0;
  std::uint64_t corrections_ = 0;
  std::uint64_t measurements_ = 0;
  std::uint64_t held_jumps_ = 0;
  std::uint64_t occlusion_rejections_ = 0;
  std::uint64_t anchor_returns_ = 0;
  std::uint64_t reanchors_ = 0;
  std::uint64_t false_anchors_ = 0;
  std::uint64_t doubtful_departures_ = 0;
  // The vergence last verged on the current target (since the last command or saccade).
  bool anchored_ = false;
  double anchor_rad_ = 0.0;
  double anchor_confidence_ = 0.0;  // Of the recent readings that verified the anchor.
  // Whether the verging eye's fovea has shown new content since the anchor was last verged on:
  // only then can something have come in front of it.
  bool verging_view_changed_ = false;
  // Since when (the measurement's stamp) the eye has been verged far from the anchor, and where.
  std::optional<std::int64_t> elsewhere_since_ns_;
  double elsewhere_rad_ = 0.0;
  bool verged_ = false;            // The vergence error has been small since the last command.
  double pending_jump_rad_ = 0.0;  // A large error waiting for confirmation.
  std::int64_t pending_jump_since_ns_ = 0;  // The stamp of the first reading of that jump.
  // A measurement below min_confidence (but above a third of it) waiting for the next to agree;
  // the vergence applied since it was measured, to compare like with like.
  bool weak_pending_ = false;
  double weak_error_rad_ = 0.0;
  double applied_since_weak_rad_ = 0.0;
  // Readings below a third of min_confidence agreeing in a row (faint_reading_persists).
  int faint_agreements_ = 0;
  double faint_error_rad_ = 0.0;
  double applied_since_faint_rad_ = 0.0;
  std::uint64_t faint_steps_ = 0;
};

}  // namespace cambio::control
