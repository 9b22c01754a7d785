#pragma once

// A recorded run (run_trace.hpp): a row per control-rate sample, the joints at each, key frames
// and the newest reach, as the TraceRecorder (trace_recorder.hpp) saw them.

#include <array>
#include <cstddef>
#include <limits>
#include <span>
#include <string>
#include <vector>

#include "cambio/control/arm_command.hpp"
#include "cambio/control/gaze_command.hpp"
#include "cambio/hal/image.hpp"

namespace cambio::app {

inline constexpr double kNoValue = std::numeric_limits<double>::quiet_NaN();

/// One joint at one sample (rad). command_rad is NaN while the joint is commanded in velocity
/// mode or no target frame has arrived; believed_rad is NaN for a joint no believed-state
/// channel covers.
struct TraceJointSample {
  double command_rad = kNoValue;
  double believed_rad = kNoValue;
  double true_rad = kNoValue;
};

/// One sample of everything but the joints. Angles are the true gaze errors: the angle
/// between an eye's true optical axis and the ray from its true optical centre to its target
/// point. The dominant eye's target point is target_W_m: the gaze loop's commanded point
/// (GazeStatus::target_W_m), except while pursuing a named target object: the point of that
/// object the dominant eye's true axis met when pursuit began, moving with the object; and
/// without a gaze loop: the named object's true centre. The verging eye's target point is where the
/// dominant eye's true axis meets the scene (GroundTruth::cast_ray); when it meets nothing, the
/// point of that axis closest to target_W_m. NaN where there is no target.
struct TraceRow {
  double time_s = 0.0;  ///< Since the recorder's first cycle (the run's start).
  bool disparity_valid = false;
  double disparity_px = kNoValue;
  double disparity_confidence = 0.0;
  bool gaze_status = false;  ///< A GazeStatus was read (a gaze loop runs).
  control::GazeAction action = control::GazeAction::kHold;
  bool saccade_active = false;
  std::array<double, 3> target_W_m{kNoValue, kNoValue, kNoValue};
  double dominant_gaze_error_deg = kNoValue;
  double verging_gaze_error_deg = kNoValue;
  double true_gaze_error_deg = kNoValue;  ///< The larger of the two (the one there is).
  /// The disparity the SSM should measure at the retinas' centres (x_left - x_right, level-0
  /// px): the point the dominant eye's true axis meets, projected into the verging camera.
  double true_disparity_px = kNoValue;
  /// The verging eye's view of its target point is blocked by another scene object, or the
  /// dominant eye's axis meets an object other than the named target object.
  bool target_occluded = false;
  /// Where the robot believes it looks (GazeStatus) and where it truly looks: the midpoint of
  /// the shortest segment between the eyes' true axes, valid when they converge in front of
  /// both eyes.
  std::array<double, 3> believed_fixation_W_m{kNoValue, kNoValue, kNoValue};
  bool believed_fixation_valid = false;
  std::array<double, 3> true_fixation_W_m{kNoValue, kNoValue, kNoValue};
  bool true_fixation_valid = false;
  double fixation_error_m = kNoValue;  ///< |believed - true| when both are valid.
  /// Which of Trace::visit_objects the dominant eye's true optical axis meets first (its index),
  /// -1 for none of them.
  int axis_object = -1;
  /// The arm of the newest accepted reach (0 left, 1 right; -1: none yet) and what it does.
  int reach_arm = -1;
  control::ReachPhase reach_phase = control::ReachPhase::kIdle;
  /// Its fingertips' midpoint from the believed joints (ArmStatus) and its distance to the reach
  /// target (the stereo estimate).
  std::array<double, 3> gripper_W_m{kNoValue, kNoValue, kNoValue};
  double gripper_distance_m = kNoValue;
  /// The same point from the true joints, and its signed distance to the target object's
  /// surface (GroundTruth::distance_to_object_m; NaN without a named target object).
  std::array<double, 3> true_gripper_W_m{kNoValue, kNoValue, kNoValue};
  double true_gripper_surface_m = kNoValue;
};

/// The newest reach as the trace saw it (the arms' ArmStatus against the ground truth).
struct ReachRecord {
  bool accepted = false;        ///< A reach was accepted (ArmStatus::command_ns set).
  int arm = -1;                 ///< 0 left, 1 right.
  double command_s = kNoValue;  ///< When it was accepted, since the start.
  double touch_s = kNoValue;    ///< When the touch sensor stopped it.
  /// The target the arm reached for: the head's stereo estimate for a fixation target.
  std::array<double, 3> estimate_W_m{kNoValue, kNoValue, kNoValue};
  /// Where the dominant eye's true optical axis met the target object at the command (ground
  /// truth); NaN when it met something else or nothing.
  std::array<double, 3> true_target_W_m{kNoValue, kNoValue, kNoValue};
  double estimated_target_error_m = kNoValue;  ///< |estimate - true_target|.
  /// At the touch: |the gap| between the gripper's true contact geometry (what its touch sensor
  /// covers) and the target object's surface (GroundTruth::end_effector_gap_m).
  double touch_position_error_m = kNoValue;
  control::ReachPhase final_phase = control::ReachPhase::kIdle;
  /// A reach was refused (the arms' message), the last one.
  bool refused = false;
  std::string refusal;
};

/// Both eyes rendered at one time by the ground truth (rig cameras at their intrinsics).
struct KeyFrame {
  double time_s = 0.0;  ///< When it was rendered (the first sample at or after the asked time).
  std::string camera;
  hal::Image image;
};

/// A recorded run. Joints are stored row-major: rows.size() x joint_names.size().
struct Trace {
  std::vector<std::string> joint_names;  ///< Rig order.
  int dominant_pan_joint = -1;           ///< Index into joint_names; -1 if not given.
  int verging_pan_joint = -1;
  /// The scene objects whose visits are recorded (TraceRow::axis_object).
  std::vector<std::string> visit_objects;
  std::vector<TraceRow> rows;
  std::vector<TraceJointSample> joints;
  std::vector<KeyFrame> key_frames;
  ReachRecord reach;
  /// The preallocated rows ran out (kMaxTraceRows): samples after the last row were dropped.
  bool truncated = false;
  /// What went wrong while recording without stopping it (a key frame that could not render).
  std::vector<std::string> problems;

  std::size_t joint_count() const { return joint_names.size(); }
  std::span<const TraceJointSample> joints_at(std::size_t row) const {
    return std::span<const TraceJointSample>(joints).subspan(row * joint_count(), joint_count());
  }
  /// Appends a row and its joints (joint_count() of them). Throws std::invalid_argument
  /// otherwise. For the recorder and for tests that build traces by hand.
  void add_row(const TraceRow& row, std::span<const TraceJointSample> joint_samples);
};

/// Rows beyond this are not recorded (with the joints, about 400 MB for the 15-joint rig).
inline constexpr std::size_t kMaxTraceRows = std::size_t{1} << 20;

}  // namespace cambio::app
