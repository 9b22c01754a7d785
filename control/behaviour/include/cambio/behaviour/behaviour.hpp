#pragma once

#include <cstdint>
#include <memory>
#include <span>
#include <string>
#include <string_view>

#include <Eigen/Geometry>

#include "cambio/control/arm_command.hpp"
#include "cambio/control/gaze_command.hpp"
#include "cambio/hal/camera.hpp"
#include "cambio/perception/sensory_servo.hpp"

namespace cambio::behaviour {

/// What a behaviour sees at each step (the paper's Decision Making Module inputs). Pointers are
/// valid during the call only; null until the first of their kind has arrived.
struct Observation {
  std::int64_t now_ns = 0;                          ///< The run's clock.
  double run_time_s = 0.0;                          ///< Since the behaviour started.
  const perception::SsmSummary* ssm = nullptr;      ///< Newest SSM summary.
  const perception::SsmFrame* ssm_frame = nullptr;  ///< Newest SSM frame with its feature maps.
  const control::GazeStatus* gaze = nullptr;        ///< Newest gaze loop status.
  const control::ArmStatus* arms = nullptr;         ///< Newest arm status (none on a head rig).
  /// The names of the SSM's feature maps: ssm_frame->maps[eye].map(level, i) is map
  /// feature_map_names[i] (e.g. "intensity", "log@1.4", "sobel_x"; firmware_config/perception).
  std::span<const std::string> feature_map_names;
  /// Believed joint positions (encoders), rig order, and their names.
  std::span<const double> q_believed_rig_rad;
  std::span<const std::string> joint_names;
  /// The dominant eye: which one, its description (intrinsics) and its believed pose in the
  /// robot's base frame (OpenCV optical frame: z forward, x right, y down).
  hal::Eye dominant_eye = hal::Eye::kLeft;
  const hal::CameraInfo* dominant_camera = nullptr;
  Eigen::Isometry3d X_W_dominant_camera = Eigen::Isometry3d::Identity();
};

/// The outcome of an action: sent (possibly clamped; `message` says what was clamped) or not
/// sent (`message` says why).
struct ActionResult {
  bool sent = false;
  std::string message;
};

/// What a behaviour (or the console) can ask of the robot. Each call sends one command; the
/// robot carries it out over the following control cycles (watch Observation::gaze / arms).
/// The head and the arms each take the newest command at their next cycle: a second gaze (or
/// arm) action before that replaces the first (one per step, or across steps).
class Actions {
 public:
  virtual ~Actions() = default;
  /// Fixate (visual servoing, the neck rule) a pixel of the dominant eye's image / a point.
  virtual ActionResult look_at_pixel(double u_px, double v_px) = 0;
  virtual ActionResult look_at_point(const Eigen::Vector3d& p_W_m) = 0;
  /// Saccade (at the joints' velocity and acceleration limits), then fixate.
  virtual ActionResult saccade_to_pixel(double u_px, double v_px) = 0;
  virtual ActionResult saccade_to_point(const Eigen::Vector3d& p_W_m) = 0;
  /// Pan positive to the robot's left, tilt positive looking down (rad), from the gaze now.
  virtual ActionResult saccade_by_angles(double pan_rad, double tilt_rad) = 0;
  virtual ActionResult pursue() = 0;
  virtual ActionResult hold() = 0;
  virtual ActionResult verge(bool on) = 0;
  /// Reach what the head fixates (stereo estimate) / a point, with an arm (nearest by default).
  virtual ActionResult reach_fixated(control::ArmSide arm = control::ArmSide::kNearest) = 0;
  virtual ActionResult reach_point(const Eigen::Vector3d& p_W_m,
                                   control::ArmSide arm = control::ArmSide::kNearest) = 0;
  virtual ActionResult grasp(control::ArmSide arm = control::ArmSide::kNearest) = 0;
  virtual ActionResult release(control::ArmSide arm = control::ArmSide::kNearest) = 0;
  /// Moves one joint to a position (rad), clamped to its limits.
  virtual ActionResult move_joint(std::string_view joint_name, double position_rad) = 0;
  /// Asks the SSM for features besides what the gaze needs (motion, moments, maps), from the
  /// next frame on; the request stays until replaced.
  virtual ActionResult request_features(const perception::FeatureRequest& features) {
    (void)features;
    return {false, "this robot takes no feature requests"};
  }
};

/// A user's decision making (attention, learning, a task): it runs in its own loop at a rate the
/// experiment sets, never on the control loop's thread, so it may allocate and take its time
/// (within its period). Construct from BehaviourParams (see registry.hpp).
class Behaviour {
 public:
  virtual ~Behaviour() = default;
  /// Called once, at the first step, before step().
  virtual void start(const Observation& observation, Actions& actions) {
    (void)observation;
    (void)actions;
  }
  /// Called at the behaviour's rate.
  virtual void step(const Observation& observation, Actions& actions) = 0;
  /// One line on what it is doing, for the console's status and the run's report.
  virtual std::string status() const { return {}; }
};

}  // namespace cambio::behaviour
