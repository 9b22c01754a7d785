#pragma once

#include <array>
#include <cstdint>
#include <string_view>

namespace cambio::control {

/// What the gaze loop is asked to do (the paper's Control Module commands for the head).
enum class GazeAction : std::uint8_t {
  kHold,     ///< Keep every head joint where it is commanded now.
  kFixate,   ///< Servo the dominant eye onto a target (visual servoing, the 30° neck rule).
  kSaccade,  ///< Jump to a target at the joints' velocity and acceleration limits, then fixate.
  kPursue,   ///< Follow what the dominant eye's fovea sees, from the SSM's motion estimate.
  /// Move one head joint (joint_rig_index) to position_rad, clamped to its limits, then hold.
  kMoveJoint,
  /// Only switch vergence on or off (GazeCommand::verge); whatever the head does goes on.
  kVerge,
};

enum class GazeTargetKind : std::uint8_t {
  kNone,    ///< No target (hold and pursue need none: pursuit follows what is fixated).
  kPoint,   ///< A point in the robot's base frame (point_W_m).
  kPixel,   ///< A pixel of the dominant eye's image at the time of the command (pixel_px).
  kAngles,  ///< An angular displacement of the gaze from where it points now (angles_rad).
};

/// Where to look. Trivially copyable: it travels through SeqlockChannel.
struct GazeTarget {
  GazeTargetKind kind = GazeTargetKind::kNone;
  std::array<double, 3> point_W_m{};  ///< kPoint: x forward, y left, z up (m).
  std::array<double, 2> pixel_px{};   ///< kPixel: (u right, v down), level-0 pixels.
  /// kAngles: (pan, tilt): pan positive to the robot's left, tilt positive looking down (rad).
  std::array<double, 2> angles_rad{};
};

/// One command to the gaze loop; a new sequence number is a new command.
struct GazeCommand {
  std::uint64_t sequence = 0;
  GazeAction action = GazeAction::kHold;
  GazeTarget target;
  bool verge = true;          ///< The other eye verges on what the dominant eye fixates.
  int joint_rig_index = -1;   ///< kMoveJoint: the joint, rig order.
  double position_rad = 0.0;  ///< kMoveJoint: where to.
};

/// Why the gaze loop refused a command (it holds, or servoes, instead of carrying it out).
enum class GazeRefusal : std::uint8_t {
  kNone,
  kTargetUnresolved,    ///< Behind the eye, not finite, or beyond the distances a target may be.
  kOutOfReach,          ///< No head pose within the joints' limits looks at it.
  kSaccadeUnplannable,  ///< The joints' velocity and acceleration limits give no saccade.
  kNotAHeadJoint,       ///< A joint move for a joint the gaze does not drive.
  kTrackingFault,       ///< A head joint stopped following its command: the loop holds.
};

constexpr std::string_view to_string(GazeRefusal refusal) {
  switch (refusal) {
    case GazeRefusal::kNone:
      return "none";
    case GazeRefusal::kTargetUnresolved:
      return "target behind the eye, not finite or too far";
    case GazeRefusal::kOutOfReach:
      return "beyond the joints' reach";
    case GazeRefusal::kSaccadeUnplannable:
      return "no saccade within the joints' velocity and acceleration limits";
    case GazeRefusal::kNotAHeadJoint:
      return "not a head joint, or a position beyond its limits";
    case GazeRefusal::kTrackingFault:
      return "a head joint does not follow its command (tracking fault): the head holds";
  }
  return "unknown";
}

/// What the gaze loop believes and does, published every control cycle.
struct GazeStatus {
  std::int64_t stamp_ns = 0;
  GazeAction action = GazeAction::kHold;
  std::uint64_t commands_applied = 0;
  std::uint64_t commands_refused = 0;
  GazeRefusal last_refusal = GazeRefusal::kNone;  ///< Why the newest refused command was.
  bool saccade_active = false;  ///< The dominant eye is on a saccade's trajectory.
  /// Head joints follow a joint trajectory (JointTrajectory): no servo, no vergence.
  bool trajectory_active = false;
  /// Frozen this cycle: a joint loop holds or a head joint is not driven (CommandTracking).
  bool joints_held = false;
  /// A head joint stopped following its command: the loop holds to the end of the run.
  bool tracking_fault = false;
  bool target_set = false;
  /// The point the dominant eye is servoed to, from its own kinematics (base frame, m); a
  /// target given as a direction is placed at the servo's default depth.
  std::array<double, 3> target_W_m{};
  /// Where the robot believes it looks: the point nearest both eyes' believed optical axes
  /// (base frame, m); invalid when the axes are parallel or diverge.
  std::array<double, 3> believed_fixation_W_m{};
  bool believed_fixation_valid = false;
  /// right eye pan - left eye pan as commanded (rad): 0 parallel, > 0 converged, never < 0.
  double vergence_rad = 0.0;
  bool disparity_valid = false;
  double disparity_px = 0.0;
  double disparity_confidence = 0.0;
  /// The dominant eye's image error to its target, from the believed kinematics (px).
  double feature_error_px = 0.0;
};

}  // namespace cambio::control
