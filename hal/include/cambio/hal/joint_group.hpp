#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <span>
#include <string>
#include <vector>

#include "cambio/hal/drive_state.hpp"
#include "cambio/hal/status.hpp"

namespace cambio::hal {

struct JointLimits {
  double min_position_rad = 0.0;
  double max_position_rad = 0.0;
  double max_velocity_rad_s = 0.0;
  double max_acceleration_rad_s2 = 0.0;
  double max_effort_nm = 0.0;  ///< 0 means "not limited by the stack" (the drive limits it).
};

/// Status bits of one joint (bitwise OR of these). Who sets each:
///  - the backend: kJointCommandClamped, kJointAtLimit, kJointFault (drive in fault or fault
///    reaction), kJointNotEnabled (drive not operation enabled), kJointCommLost (heartbeat or
///    feedback frames missed; sticky until a fault reset), kJointStale where it can tell
///    (a CAN group after missed SYNC answers), kJointHoming;
///  - the joint loop: kJointStale when a reading's stamp is older than its feedback timeout, and
///    it latches kJointFault and kJointCommLost until a fault reset clears them.
enum JointStatusBits : std::uint32_t {
  kJointOk = 0,
  kJointCommandClamped = 1u << 0,  ///< The last command exceeded a limit and was clamped.
  kJointAtLimit = 1u << 1,         ///< The joint sits at a position limit.
  kJointFault = 1u << 2,           ///< The drive latched a fault (sticky until reset).
  kJointStale = 1u << 3,           ///< The reading is older than the freshness bound.
  kJointNotEnabled = 1u << 4,      ///< The drive is not in its operation-enabled state.
  kJointCommLost = 1u << 5,        ///< Heartbeat or feedback missed (sticky until reset).
  /// The drive is homing (DriveRequest::kHome): not driven, its position not yet in the homed
  /// frame. Set with kJointNotEnabled.
  kJointHoming = 1u << 6,
};

/// Bits after which the joint loop stops sending motion to the whole rig until a reset.
inline constexpr std::uint32_t kJointLatchingBits = kJointFault | kJointCommLost;

/// What the encoders say about one joint (the believed state, never the world's true state).
struct JointState {
  double position_rad = 0.0;
  double velocity_rad_s = 0.0;
  double effort_nm = 0.0;
  /// When this joint's feedback was sampled, on the run's clock (ns). Each CAN node answers in
  /// its own frame, so joints of one group may differ.
  std::int64_t stamp_ns = 0;
  /// The drive's last CiA 301/402 emergency error code (e.g. 0x7300 sensor, 0x8611 following
  /// error); 0 when none. Kept until a fault reset.
  std::uint16_t error_code = 0;
  DriveState drive_state = DriveState::kNotReadyToSwitchOn;
  std::uint32_t status_bits = kJointOk;
};

enum class CommandMode : std::uint8_t { kPosition, kVelocity };

/// One target. In position mode (CiA 402 cyclic synchronous position) the drive may add the
/// feed-forward terms to its own velocity and torque loops; in velocity mode (cyclic synchronous
/// velocity) `velocity_feedforward_rad_s` is ignored and `effort_feedforward_nm` is added.
struct JointCommand {
  CommandMode mode = CommandMode::kPosition;
  double value = 0.0;  ///< rad for kPosition, rad/s for kVelocity.
  double velocity_feedforward_rad_s = 0.0;
  double effort_feedforward_nm = 0.0;
};

/// Makes a command safe to execute: a position beyond [min, max] or a velocity beyond
/// +-max_velocity is clamped; a non-finite value becomes "hold" (velocity 0). Returns true if the
/// command changed (the caller flags kJointCommandClamped). Real-time safe.
/// Feed-forward terms are clamped too (velocity to +-max_velocity, effort to +-max_effort when
/// that is set); a non-finite feed-forward becomes 0.
inline bool clamp_command(JointCommand& command, double min_position_rad, double max_position_rad,
                          double max_velocity_rad_s, double max_effort_nm = 0.0) noexcept {
  if (!std::isfinite(command.value)) {
    command = {CommandMode::kVelocity, 0.0, 0.0, 0.0};
    return true;
  }
  bool clamped = false;
  auto limit = [&clamped](double& value, double low, double high) {
    const double limited = std::isfinite(value) ? std::clamp(value, low, high) : 0.0;
    clamped = clamped || limited != value;
    value = limited;
  };
  if (command.mode == CommandMode::kPosition) {
    limit(command.value, min_position_rad, max_position_rad);
  } else {
    limit(command.value, -max_velocity_rad_s, max_velocity_rad_s);
  }
  limit(command.velocity_feedforward_rad_s, -max_velocity_rad_s, max_velocity_rad_s);
  const double effort_bound =
      max_effort_nm > 0.0 ? max_effort_nm : std::numeric_limits<double>::infinity();
  limit(command.effort_feedforward_nm, -effort_bound, effort_bound);
  return clamped;
}

inline bool clamp_command(JointCommand& command, const JointLimits& limits) noexcept {
  return clamp_command(command, limits.min_position_rad, limits.max_position_rad,
                       limits.max_velocity_rad_s, limits.max_effort_nm);
}

struct JointGroupInfo {
  std::string name;                 ///< e.g. "head", "left_arm".
  std::string backend;              ///< The name its backend registered with.
  std::vector<std::string> joints;  ///< Joint names, in the order of read()/write() spans.
  std::vector<JointLimits> limits;  ///< One per joint, same order.
  /// The group's own joint-loop rate (a CAN group's SYNC rate), as a ros2_control hardware
  /// component's read/write rate; 0 = the rig's loops.joint.rate_hz.
  double rate_hz = 0.0;
};

/// A set of joints driven by one backend. Every call below is made from the joint loop's thread,
/// in this order each cycle: read() -> write() -> sync(); request() whenever the loop forwards a
/// lifecycle request. None blocks or allocates (real-time safe).
class JointGroup {
 public:
  /// request() addresses every joint of the group.
  static constexpr int kAllJoints = -1;

  virtual ~JointGroup() = default;

  /// Thread-safe; real-time safe.
  virtual const JointGroupInfo& info() const = 0;

  /// Fills `out` (size == joint count, else kRejected) with the newest readings, each with its
  /// own stamp, drive state, error code and status bits, and `stamp_ns` with the newest of the
  /// joints' stamps. kFault if any joint is faulted or lost; kOk otherwise.
  virtual Status read(std::span<JointState> out, std::int64_t& stamp_ns) = 0;

  /// Sends one target per joint (size == joint count, else kRejected). Targets beyond a limit
  /// are clamped and flagged with kJointCommandClamped, never executed. A joint that is not
  /// operation enabled ignores its target (its drive holds or is unpowered).
  virtual Status write(std::span<const JointCommand> commands) = 0;

  /// Lifecycle request for one joint (index in info().joints) or kAllJoints. Non-blocking: it is
  /// recorded, and the resulting drive states show on later read()s. kRejected for a bad index.
  virtual Status request(DriveRequest request, int joint = kAllJoints) = 0;

  /// Called once per joint-loop cycle after write(): the point where a CAN group sends SYNC so
  /// the drives latch this cycle's targets together. Backends that apply targets as they are
  /// written return kOk.
  virtual Status sync() { return Status::kOk; }
};

}  // namespace cambio::hal
