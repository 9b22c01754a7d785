#pragma once

#include <cstdint>
#include <memory>
#include <mutex>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "cambio/behaviour/behaviour.hpp"
#include "cambio/control/arm_command.hpp"
#include "cambio/control/believed_joints.hpp"
#include "cambio/control/gaze_command.hpp"
#include "cambio/control/joint_trajectory.hpp"
#include "cambio/hal/hardware_info.hpp"
#include "cambio/hal/seqlock_channel.hpp"

namespace cambio::app {

/// The robot's actions as commands on the control loops' channels: what the console and user
/// behaviours send. Checks what it can before sending (a pixel inside the image, a finite point,
/// a known joint within its limits: clamped, and the result says so) and refuses, saying why,
/// what no loop of this run carries out (an arm action on a run without an arm controller).
/// What the loops refuse later (a target behind the eye, an unreachable point) shows in their
/// status channels.
///
/// The channels take one writer each: every call holds a mutex while it writes, so the console
/// and a behaviour may both act (neither runs on a real-time loop's thread).
class RobotActions final : public behaviour::Actions {
 public:
  struct Setup {
    /// The rig's joints in rig order (the command channels' joint indices).
    std::vector<std::string> rig_joint_order;
    /// The joints the gaze loop moves (the head); every other joint belongs to the arms.
    std::vector<std::string> head_joints;
    /// The dominant eye's image size: pixel targets must lie inside it.
    int image_width_px = 0;
    int image_height_px = 0;
    /// Whether the other eye verges, until a verge action changes it.
    bool verge = true;
  };

  /// The loops' command channels; `arms` null: the run has no arm controller; `features` null:
  /// no feature requests.
  struct Channels {
    hal::SeqlockChannel<control::GazeCommand>* gaze = nullptr;
    hal::SeqlockChannel<control::ArmCommand>* arms = nullptr;
    hal::SeqlockChannel<perception::FeatureRequest>* features = nullptr;
    /// Joint trajectories for the gaze loop (head joints) and the arm loop; null: none.
    hal::SeqlockChannel<control::JointTrajectory>* head_trajectories = nullptr;
    hal::SeqlockChannel<control::JointTrajectory>* arm_trajectories = nullptr;
  };

  /// Throws std::invalid_argument for a joint in `setup` that `hardware` does not describe, or
  /// no gaze channel.
  RobotActions(const hal::HardwareInfo& hardware, Setup setup, Channels channels);

  behaviour::ActionResult look_at_pixel(double u_px, double v_px) override;
  behaviour::ActionResult look_at_point(const Eigen::Vector3d& p_W_m) override;
  behaviour::ActionResult saccade_to_pixel(double u_px, double v_px) override;
  behaviour::ActionResult saccade_to_point(const Eigen::Vector3d& p_W_m) override;
  behaviour::ActionResult saccade_by_angles(double pan_rad, double tilt_rad) override;
  behaviour::ActionResult pursue() override;
  behaviour::ActionResult hold() override;
  behaviour::ActionResult verge(bool on) override;
  behaviour::ActionResult reach_fixated(control::ArmSide arm) override;
  behaviour::ActionResult reach_point(const Eigen::Vector3d& p_W_m, control::ArmSide arm) override;
  behaviour::ActionResult grasp(control::ArmSide arm) override;
  behaviour::ActionResult release(control::ArmSide arm) override;
  behaviour::ActionResult move_joint(std::string_view joint_name, double position_rad) override;
  behaviour::ActionResult request_features(const perception::FeatureRequest& features) override;

  /// Where the joints are, for trajectories to start from (set before the run; without it
  /// trajectories are refused).
  void set_measured_joints(control::BelievedJoints measured);
  /// Sends `trajectory` (every field but joint_rig_index and sequence) for the joints `names`
  /// (its joint_count of them): to the gaze loop when they are all the head's, to the arm loop
  /// when they are all the arms'. Refused, saying why, for an unknown or repeated joint, head and
  /// arm joints together, or anything check_joint_trajectory() finds against the joints' limits
  /// and where they are measured now.
  behaviour::ActionResult follow_trajectory(std::span<const std::string> names,
                                            control::JointTrajectory trajectory);

  bool verging() const;
  /// Commands sent so far on each channel.
  std::uint64_t gaze_commands_sent() const;
  std::uint64_t arm_commands_sent() const;
  std::uint64_t trajectories_sent() const;

 private:
  behaviour::ActionResult pixel_command(control::GazeAction action, double u_px, double v_px);
  behaviour::ActionResult point_command(control::GazeAction action, const Eigen::Vector3d& p_W_m);
  behaviour::ActionResult send(control::GazeCommand command);
  behaviour::ActionResult send(control::ArmCommand command);

  struct Joint {
    std::string name;
    hal::JointLimits limits;
    bool head = false;
  };

  /// The joint of that name, or end() with `why` saying so (and the nearest name).
  std::vector<Joint>::const_iterator find_joint(std::string_view joint_name,
                                                std::string& why) const;

  std::vector<Joint> joints_;  // Rig order.
  int image_width_px_ = 0;
  int image_height_px_ = 0;
  Channels channels_;
  mutable std::mutex mutex_;
  bool verge_ = true;
  std::uint64_t gaze_sequence_ = 0;
  std::uint64_t arm_sequence_ = 0;
  std::uint64_t trajectory_sequence_ = 0;
  std::unique_ptr<control::BelievedJoints> measured_;  // Read under mutex_.
  std::vector<double> measured_rad_;                   // Rig order; under mutex_.
};

}  // namespace cambio::app
