#pragma once

#include <array>
#include <cstdint>
#include <string_view>

namespace cambio::control {

/// Which arm a command is for.
enum class ArmSide : std::uint8_t {
  kNearest,  ///< The arm whose shoulder is nearer the target (reach); both arms otherwise.
  kLeft,
  kRight,
};

/// What the arms are asked to do (the paper's Control Module commands for the arms).
enum class ArmAction : std::uint8_t {
  kHold,     ///< Keep the arm where it is commanded now (stops a reach).
  kReach,    ///< Servo the gripper to a point; stop on the touch sensor (or at the point).
  kGrasp,    ///< Close the gripper (until it stops on what it holds).
  kRelease,  ///< Open the gripper.
  /// Move one arm joint (joint_rig_index) to position_rad, clamped to its limits; stops a reach.
  kMoveJoint,
};

/// Where a reach goes.
enum class ReachTargetKind : std::uint8_t {
  kPoint,     ///< point_W_m, in the robot's base frame.
  kFixation,  ///< What the head fixates now, from its own stereo geometry (never ground truth).
};

/// One command to the arms; a new sequence number is a new command. Trivially copyable: it
/// travels through SeqlockChannel.
struct ArmCommand {
  std::uint64_t sequence = 0;
  ArmAction action = ArmAction::kHold;
  ArmSide arm = ArmSide::kNearest;
  ReachTargetKind target = ReachTargetKind::kFixation;
  std::array<double, 3> point_W_m{};  ///< kPoint: x forward, y left, z up (m).
  int joint_rig_index = -1;           ///< kMoveJoint: the joint, rig order.
  double position_rad = 0.0;          ///< kMoveJoint: where to.
};

/// Where one arm's reach stands.
enum class ReachPhase : std::uint8_t {
  kIdle,      ///< No reach since the last hold (or ever).
  kReaching,  ///< Servoing the gripper to the target.
  kTouching,  ///< The touch sensor fired: the arm stopped there.
  kArrived,   ///< At the target point without a touch.
  kRefused,   ///< The last command could not be carried out; see ArmStatus::message.
};

/// What the arms believe and do, published every control cycle.
struct ArmStatus {
  struct Arm {
    ReachPhase phase = ReachPhase::kIdle;
    bool gripper_closed = false;
    std::int64_t command_ns = 0;  ///< When the current reach was accepted.
    std::int64_t touch_ns = 0;    ///< When the touch sensor fired during it (0: not yet).
    /// The reach target (base frame, m): for kFixation, the stereo estimate at the command.
    std::array<double, 3> target_W_m{};
    /// The gripper's tip from the believed joints (base frame, m).
    std::array<double, 3> gripper_W_m{};
    double distance_to_target_m = 0.0;
  };
  std::int64_t stamp_ns = 0;
  std::uint64_t commands_applied = 0;
  std::array<Arm, 2> arms{};  ///< [0] left, [1] right.
  /// Frozen this cycle: a joint loop holds or an arm joint is not driven (CommandTracking).
  bool joints_held = false;
  /// An arm joint stopped following its command: the arms hold to the end of the run.
  bool tracking_fault = false;
  /// Why the last refused command was refused (out of reach, beyond a joint limit, no
  /// fixation), NUL-terminated.
  std::array<char, 160> message{};

  std::string_view refusal() const { return std::string_view(message.data()); }
};

}  // namespace cambio::control
