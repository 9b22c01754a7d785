#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include "cambio/hal/status.hpp"

namespace cambio::hal {

struct JointLimits {
  double min_position_rad = 0.0;
  double max_position_rad = 0.0;
  double max_velocity_rad_s = 0.0;
  double max_acceleration_rad_s2 = 0.0;
  double max_effort_nm = 0.0;  ///< 0 means "not limited by the stack" (the drive limits it).
};

/// Sticky and per-sample status bits of one joint (bitwise OR of these).
enum JointStatusBits : std::uint32_t {
  kJointOk = 0,
  kJointCommandClamped = 1u << 0,  ///< The last command exceeded a limit and was clamped.
  kJointAtLimit = 1u << 1,         ///< The joint sits at a position limit.
  kJointFault = 1u << 2,           ///< The drive latched a fault (sticky until cleared).
  kJointStale = 1u << 3,           ///< The reading is older than the freshness bound.
  kJointNotEnabled = 1u << 4,      ///< The drive is not in its operation-enabled state.
  kJointCommLost = 1u << 5,        ///< Heartbeat or feedback missed (sticky).
};

/// What the encoders say about one joint (the believed state, never the world's true state).
struct JointState {
  double position_rad = 0.0;
  double velocity_rad_s = 0.0;
  double effort_nm = 0.0;
  std::uint32_t status_bits = kJointOk;
};

enum class CommandMode : std::uint8_t { kPosition, kVelocity };

struct JointCommand {
  CommandMode mode = CommandMode::kPosition;
  double value = 0.0;  ///< rad for kPosition, rad/s for kVelocity.
};

/// Makes a command safe to execute: a position beyond [min, max] or a velocity beyond
/// +-max_velocity is clamped; a non-finite value becomes "hold" (velocity 0). Returns true if the
/// command changed (the caller flags kJointCommandClamped). Real-time safe.
inline bool clamp_command(JointCommand& command, double min_position_rad, double max_position_rad,
                          double max_velocity_rad_s) noexcept {
  if (!std::isfinite(command.value)) {
    command = {CommandMode::kVelocity, 0.0};
    return true;
  }
  const double limited = command.mode == CommandMode::kPosition
                             ? std::clamp(command.value, min_position_rad, max_position_rad)
                             : std::clamp(command.value, -max_velocity_rad_s, max_velocity_rad_s);
  const bool clamped = limited != command.value;
  command.value = limited;
  return clamped;
}

inline bool clamp_command(JointCommand& command, const JointLimits& limits) noexcept {
  return clamp_command(command, limits.min_position_rad, limits.max_position_rad,
                       limits.max_velocity_rad_s);
}

struct JointGroupInfo {
  std::string name;                 ///< e.g. "head", "left_arm".
  std::string backend;              ///< "sim", "socketcan".
  std::vector<std::string> joints;  ///< Joint names, in the order of read()/write() spans.
  std::vector<JointLimits> limits;  ///< One per joint, same order.
};

/// A set of joints driven by one backend. read() and write() are called from the joint loop.
class JointGroup {
 public:
  virtual ~JointGroup() = default;

  /// Thread-safe; real-time safe.
  virtual const JointGroupInfo& info() const = 0;

  /// Fills `out` (size == joint count, else kRejected) with the newest encoder readings and
  /// `stamp_ns` with their time on the group's clock. Real-time safe.
  virtual Status read(std::span<JointState> out, std::int64_t& stamp_ns) = 0;

  /// Sends one target per joint (size == joint count, else kRejected). Targets beyond a limit
  /// are clamped and flagged with kJointCommandClamped, never executed. Real-time safe.
  virtual Status write(std::span<const JointCommand> commands) = 0;
};

}  // namespace cambio::hal
