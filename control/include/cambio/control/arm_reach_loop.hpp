#pragma once

#include <array>
#include <memory>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "cambio/control/arm_chain.hpp"
#include "cambio/control/arm_command.hpp"
#include "cambio/control/arm_reach_check.hpp"
#include "cambio/control/believed_joints.hpp"
#include "cambio/control/command_tracking.hpp"
#include "cambio/control/gaze_command.hpp"
#include "cambio/control/joint_frames.hpp"
#include "cambio/control/joint_trajectory_follower.hpp"
#include "cambio/control/kinematics.hpp"
#include "cambio/control/trajectory_inbox.hpp"
#include "cambio/hal/hardware_info.hpp"
#include "cambio/hal/loop.hpp"
#include "cambio/hal/seqlock_channel.hpp"
#include "cambio/hal/touch_sensor.hpp"

namespace cambio::control {

namespace detail {
class ArmReachLaw;
}

/// Settings of the arm loop. No tuning defaults here: the experiment file's loader holds them.
struct ArmReachParams {
  /// The arms' rig groups, [0] left, [1] right; "" for a side the rig does not have.
  std::array<std::string, 2> groups;
  double gain_per_s = 0.0;     ///< The servo's lambda: the fingertips' speed is gain x distance.
  double max_speed_m_s = 0.0;  ///< Cap on the fingertips' speed.
  /// The speed cap grows from zero at this rate after a reach starts (m/s^2), so the joints
  /// start within their acceleration limits.
  double max_acceleration_m_s2 = 0.0;
  /// The servo aims this far past the target along the approach (a guarded move): the surface
  /// the stereo estimate puts there may lie a little behind it, and the touch is met at speed
  /// gain x probe instead of approached asymptotically. Without a touch the reach stops there.
  double probe_depth_m = 0.0;
  /// The fingertips first go to this far in front of the target, on the horizontal line from
  /// the shoulder through it, then straight in: the fingers meet the surface head-on where the
  /// estimate is, not at a graze from below. 0: straight from where the hand is.
  double approach_m = 0.0;
  double arrive_tolerance_m = 0.0;  ///< At the servo's aim within this: arrived.
  /// Secondary task: the joints toward the reach check's solution at the aim (1/s).
  double posture_gain_per_s = 0.0;
  HandPitchRange hand_pitches;
  double gripper_speed_rad_s = 0.0;  ///< Opening and closing.
  /// How far each arm joint's command may lead its measured position before the loop faults
  /// (CommandTracking), one per hardware.joints entry (rad); empty: unbounded. A closing gripper
  /// is exempt: it squeezes what it holds.
  std::vector<double> max_tracking_error_rad;
};

/// The arms' control loop (the paper's Control Module for the arms), at the control rate, named
/// "arm". On an ArmCommand:
///  - kReach: the target is a point, or what the head fixates (GazeStatus::believed_fixation_W_m:
///    the point nearest both eyes' believed optical axes, from the vergence and the kinematics;
///    never ground truth). The arm (kNearest: the one whose shoulder is nearer; if it cannot, the
///    other) is checked with check_reach() at the command: out of reach, beyond a joint limit or
///    no fixation refuse it (ArmStatus::message says why, the arm's phase is kRefused) before
///    anything moves. Then a position-based servo (ViSP's vpServo law, computed without
///    allocating: control/src/arm_reach_law.hpp) drives the fingertips' midpoint to approach_m
///    in front of the target, then along a straight line to the target plus probe_depth_m, its
///    speed gain x distance (slowing near the target), capped and ramped, every joint within its
///    velocity and position limits, the joints drawn toward the check's solution as its
///    secondary task. The servo runs on the commanded pose (the robot's intent): the drives' lag
///    does not feed back into the law. When the arm's touch sensor reports contact the arm stops
///    where it is believed to be (touch_ns recorded, phase kTouching) and the gripper closes; at
///    the aim without a touch the phase is kArrived.
///  - kGrasp closes, kRelease opens the gripper (kNearest: both arms); kHold stops a reach;
///    kMoveJoint moves one arm joint to a position (clamped to its limits) at half its velocity
///    limit, stopping that arm's reach;
///  - a joint trajectory (from the trajectory channel, set_trajectories()) moves the arm joints it
///    names along it from where they are commanded, stopping the reaches and moves of the arms it
///    names; then they hold its last point. kHold, kReach and kMoveJoint end it; a hold of the
///    drives ends it where the joints are. A joint that is not an arm's refuses it.
/// It publishes targets for every rig joint (rig order; the arms' joints are its own, the others
/// stay at the initial pose: the gaze loop overlays the arms' joints onto its own frame) and an
/// ArmStatus each cycle.
///
/// The drives not following (CommandTracking): while a joint loop holds or an arm joint is not
/// driven the loop freezes (commands are taken, nothing moves); on the first cycle they follow
/// again it publishes the measured pose and resumes from it, a reach's speed ramped up from zero
/// again. An arm joint whose command leads its measurement by more than its
/// max_tracking_error_rad is a fault of this loop: it reports it (hal::Loop::fault_message),
/// stops every reach, holds where the joints are, refuses later commands and returns kFault to
/// the end of the run.
///
/// Real-time: everything is allocated at construction; update() never allocates, reaching or
/// not.
class ArmReachLoop final : public hal::Loop {
 public:
  /// `pose`: every rig joint's initial target, rig order. `gaze` (may be null) is read for
  /// kFixation targets; `touch` holds the arms' touch sensors ([0] left, [1] right; null: none).
  /// Throws std::invalid_argument for an arm group that is not an ArmChain, no arm at all, a pose
  /// of the wrong size or settings out of range.
  ArmReachLoop(const hal::HardwareInfo& hardware, const ArmReachParams& params,
               const JointTargetFrame& pose, BelievedJoints believed,
               const hal::SeqlockChannel<GazeStatus>* gaze,
               const hal::SeqlockChannel<ArmCommand>& commands,
               std::array<hal::TouchSensor*, 2> touch);
  ~ArmReachLoop() override;

  const std::string& name() const override { return name_; }
  hal::Status update(const hal::LoopTick& tick) noexcept override;

  /// Targets for every rig joint, rig order, each cycle.
  const hal::SeqlockChannel<JointTargetFrame>& targets() const { return targets_; }
  const hal::SeqlockChannel<ArmStatus>& status() const { return status_channel_; }
  /// The rig indices of the arms' joints: what the gaze loop takes from targets().
  const std::vector<int>& arm_rig_indices() const { return arm_rig_indices_; }
  /// The arm of a side, or null when the rig has none there.
  const ArmChain* arm(int side) const;
  /// The channel of joint trajectories for the arms (configure time; null: none).
  void set_trajectories(const hal::SeqlockChannel<JointTrajectory>* trajectories) {
    trajectories_.set_channel(trajectories);
  }
  /// Trajectories started, and those that reached their last point.
  const JointTrajectoryFollower& trajectory_follower() const { return follower_; }
  /// The arms' tracking: frozen cycles, restarts, the largest lead, a fault. Read it from the
  /// loop's thread or after the executor stopped.
  const CommandTracking& tracking() const { return tracking_; }

 private:
  struct Arm {
    bool present = false;
    ArmChain chain;
    hal::TouchSensor* touch = nullptr;
    int wrist_frame = 0;                                   // Kinematics frame of the wrist link.
    Eigen::Vector3d target_W = Eigen::Vector3d::Zero();    // The estimate reached for.
    Eigen::Vector3d aim_W = Eigen::Vector3d::Zero();       // target_W + the probe.
    Eigen::Vector3d approach_W = Eigen::Vector3d::Zero();  // In front of target_W.
    bool approaching = false;            // On the way to approach_W, before going in.
    std::array<double, 4> q_goal_rad{};  // The check's joints at the aim.
    double gripper_goal_rad = 0.0;
    int move_joint = -1;  // Tree index of a kMoveJoint in progress.
    double move_goal_rad = 0.0;
    std::int64_t ramp_from_ns = 0;  // The reach's speed cap grows from zero from here.
  };

  void apply(const ArmCommand& command, std::int64_t now_ns) noexcept;
  /// A new trajectory from the channel: started, or refused naming the joint.
  void start_trajectory(std::int64_t now_ns) noexcept;
  /// The arm side (0 left, 1 right) and chain position of a rig joint; false for none.
  bool find_arm_joint(int rig_index, int& side, std::size_t& k) const noexcept;
  // One cycle of the arms' motion (grippers, moves, reaches) while the joints follow.
  void step_arms(std::int64_t now_ns, double dt_s) noexcept;
  // The arms' status from the believed joints, then both channels written.
  void publish(std::int64_t now_ns) noexcept;
  // After a hold: the command at the measured pose, reaches ramped up again.
  void restart_from_measured(std::int64_t now_ns) noexcept;
  // A tracking fault: every reach stopped, the command where the joints are.
  void stop_on_tracking_fault() noexcept;
  // apply()'s actions. kGrasp closes, kRelease opens the grippers of `sides`.
  void set_gripper_goals(ArmAction action, const std::array<bool, 2>& sides) noexcept;
  void move_joint(const ArmCommand& command) noexcept;
  void reach(const ArmCommand& command, const std::array<bool, 2>& sides,
             std::int64_t now_ns) noexcept;
  // The command's point, or the believed fixation; false (the named sides refused) for none.
  bool reach_target(const ArmCommand& command, const std::array<bool, 2>& sides,
                    Eigen::Vector3d& target_W) noexcept;
  // kNearest: the nearer arm, else the other.
  void reach_with_nearer_arm(const Eigen::Vector3d& target_W, std::int64_t now_ns) noexcept;
  bool start_reach(int side, const Eigen::Vector3d& target_W, std::int64_t now_ns) noexcept;
  void refuse(int side, const char* why) noexcept;
  void stop(int side) noexcept;
  void reach_step(int side, std::int64_t now_ns, double dt_s) noexcept;
  // reach_step()'s steps. True when the touch sensor stopped the reach.
  bool stop_on_touch(Arm& arm, ArmStatus::Arm& s, std::int64_t now_ns) noexcept;
  // The fingertips' linear velocity per arm joint velocity, at the commanded pose.
  void tip_jacobian_W(const Arm& arm, const Eigen::Vector3d& tip,
                      Eigen::Matrix<double, 3, 4>& J_v) noexcept;
  // The servo's joint velocities toward e_W; false when it finds none.
  bool solve_joint_velocities(const Arm& arm, const Eigen::Vector3d& e_W,
                              const Eigen::Matrix<double, 3, 4>& J_v,
                              Eigen::Vector4d& qdot) noexcept;
  // Integrates qdot into the commanded joints, capped and ramped.
  void advance_joints(const Arm& arm, std::int64_t ramp_from_ns, std::int64_t now_ns, double dt_s,
                      const Eigen::Matrix<double, 3, 4>& J_v, const Eigen::Vector4d& qdot) noexcept;
  Eigen::Vector3d tip_W(const Kinematics& kinematics, const Arm& arm) const noexcept;

  std::string name_ = "arm";
  ArmReachParams params_;
  std::array<Arm, 2> arms_;
  std::vector<int> arm_rig_indices_;
  CommandTracking tracking_;
  std::array<int, 2> gripper_tracked_{-1, -1};  // Each arm's gripper in tracking_'s joints.
  std::unique_ptr<detail::ArmReachLaw> law_;
  Kinematics command_kinematics_;   // At the commanded pose: the servo's.
  Kinematics believed_kinematics_;  // At the encoders: the status's.
  std::vector<hal::JointLimits> limits_tree_;
  std::vector<int> rig_to_tree_;
  Jacobian J_W_;

  BelievedJoints believed_;
  const hal::SeqlockChannel<GazeStatus>* gaze_;
  const hal::SeqlockChannel<ArmCommand>& commands_;
  hal::SeqlockChannel<JointTargetFrame> targets_;
  hal::SeqlockChannel<ArmStatus> status_channel_;

  JointTargetFrame pose_;
  std::vector<double> q_command_tree_;
  std::vector<double> q_believed_rig_;
  std::vector<double> q_believed_tree_;
  std::uint64_t last_command_sequence_ = 0;
  TrajectoryInbox trajectories_;
  JointTrajectoryFollower follower_;
  GazeStatus gaze_status_{};
  ArmStatus status_{};
};

}  // namespace cambio::control
