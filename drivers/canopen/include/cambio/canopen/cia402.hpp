#pragma once

// CiA 402 (IEC 61800-7-201) drive profile vocabulary shared by the master and the emulated
// drives: the objects the stack uses, statusword <-> drive state, controlword commands and the
// drive-side state machine, and counts <-> rad. Header-only, no allocation.

#include <climits>
#include <cmath>
#include <cstdint>
#include <numbers>

#include "cambio/canopen/protocol.hpp"
#include "cambio/hal/drive_state.hpp"

namespace cambio::canopen::cia402 {

// Objects (CiA 402-2 §8), sub 0 unless noted, with their CANopen data types.
inline constexpr ObjectAddress kErrorCode{0x603F, 0};                 ///< UNSIGNED16
inline constexpr ObjectAddress kControlword{0x6040, 0};               ///< UNSIGNED16
inline constexpr ObjectAddress kStatusword{0x6041, 0};                ///< UNSIGNED16
inline constexpr ObjectAddress kQuickStopOptionCode{0x605A, 0};       ///< INTEGER16
inline constexpr ObjectAddress kModesOfOperation{0x6060, 0};          ///< INTEGER8
inline constexpr ObjectAddress kModesOfOperationDisplay{0x6061, 0};   ///< INTEGER8
inline constexpr ObjectAddress kPositionActualValue{0x6064, 0};       ///< INTEGER32, counts
inline constexpr ObjectAddress kFollowingErrorWindow{0x6065, 0};      ///< UNSIGNED32, counts
inline constexpr ObjectAddress kFollowingErrorTimeout{0x6066, 0};     ///< UNSIGNED16, ms
inline constexpr ObjectAddress kVelocityActualValue{0x606C, 0};       ///< INTEGER32, counts/s
inline constexpr ObjectAddress kRatedTorque{0x6076, 0};               ///< UNSIGNED32, mN m
inline constexpr ObjectAddress kTorqueActualValue{0x6077, 0};         ///< INTEGER16, 1/1000 rated
inline constexpr ObjectAddress kTargetPosition{0x607A, 0};            ///< INTEGER32, counts
inline constexpr ObjectAddress kMinSoftwarePositionLimit{0x607D, 1};  ///< INTEGER32, counts
inline constexpr ObjectAddress kMaxSoftwarePositionLimit{0x607D, 2};  ///< INTEGER32, counts
inline constexpr ObjectAddress kMaxProfileVelocity{0x607F, 0};        ///< UNSIGNED32, counts/s
inline constexpr ObjectAddress kMaxMotorSpeed{0x6080, 0};             ///< UNSIGNED32, counts/s
inline constexpr ObjectAddress kProfileAcceleration{0x6083, 0};       ///< UNSIGNED32, counts/s2
inline constexpr ObjectAddress kQuickStopDeceleration{0x6085, 0};     ///< UNSIGNED32, counts/s2
inline constexpr ObjectAddress kPositionDemandValue{0x6062, 0};       ///< INTEGER32, counts
inline constexpr ObjectAddress kVelocityOffset{0x60B1, 0};            ///< INTEGER32, counts/s
inline constexpr ObjectAddress kTorqueOffset{0x60B2, 0};              ///< INTEGER16, 1/1000 rated
inline constexpr ObjectAddress kInterpolationTimePeriod{0x60C2, 1};   ///< UNSIGNED8, value
inline constexpr ObjectAddress kInterpolationTimeIndex{0x60C2, 2};    ///< INTEGER8, 10^index s
inline constexpr ObjectAddress kTargetVelocity{0x60FF, 0};            ///< INTEGER32, counts/s
inline constexpr ObjectAddress kSupportedDriveModes{0x6502, 0};       ///< UNSIGNED32
// Homing (CiA 402-2 §12).
inline constexpr ObjectAddress kHomeOffset{0x607C, 0};          ///< INTEGER32, counts
inline constexpr ObjectAddress kHomingMethod{0x6098, 0};        ///< INTEGER8
inline constexpr ObjectAddress kHomingSwitchSpeed{0x6099, 1};   ///< UNSIGNED32, counts/s
inline constexpr ObjectAddress kHomingZeroSpeed{0x6099, 2};     ///< UNSIGNED32, counts/s
inline constexpr ObjectAddress kHomingAcceleration{0x609A, 0};  ///< UNSIGNED32, counts/s2

/// Device type (0x1000) of a CiA 402 servo drive: profile 402, "servo drive" type bits.
inline constexpr std::uint32_t kDeviceTypeServoDrive = 0x0002'0192;

/// Modes of operation (0x6060) the stack uses.
enum class Mode : std::int8_t {
  kHoming = 6,
  kCyclicSynchronousPosition = 8,
  kCyclicSynchronousVelocity = 9,
};

// Statusword bits.
inline constexpr std::uint16_t kStatusReadyToSwitchOn = 1u << 0;
inline constexpr std::uint16_t kStatusSwitchedOn = 1u << 1;
inline constexpr std::uint16_t kStatusOperationEnabled = 1u << 2;
inline constexpr std::uint16_t kStatusFault = 1u << 3;
inline constexpr std::uint16_t kStatusVoltageEnabled = 1u << 4;
inline constexpr std::uint16_t kStatusQuickStop = 1u << 5;  ///< 0 = quick stop active.
inline constexpr std::uint16_t kStatusSwitchOnDisabled = 1u << 6;
inline constexpr std::uint16_t kStatusWarning = 1u << 7;
inline constexpr std::uint16_t kStatusRemote = 1u << 9;
inline constexpr std::uint16_t kStatusTargetReached = 1u << 10;
inline constexpr std::uint16_t kStatusInternalLimitActive = 1u << 11;
/// CSP/CSV: the drive follows the target (1) or ignores it (0).
inline constexpr std::uint16_t kStatusDriveFollowsCommand = 1u << 12;
inline constexpr std::uint16_t kStatusFollowingError = 1u << 13;
// Homing mode (6) gives bits 10, 12 and 13 their own meaning (CiA 402-2 Table 73):
//   13 12 10
//    0  0  0  homing in progress
//    0  0  1  homing interrupted or not started
//    0  1  0  homing attained, target not reached (still moving onto the home position)
//    0  1  1  homing completed successfully
//    1  0  0  homing error, velocity not 0
//    1  0  1  homing error, velocity 0
inline constexpr std::uint16_t kStatusHomingAttained = 1u << 12;
inline constexpr std::uint16_t kStatusHomingError = 1u << 13;
/// Controlword bit 4 in homing mode: its rising edge starts homing, clearing it interrupts.
inline constexpr std::uint16_t kControlHomingStart = 1u << 4;

/// The drive state a statusword encodes (CiA 402-2 Table 30). Bits outside the state pattern
/// are ignored.
constexpr hal::DriveState drive_state_of(std::uint16_t statusword) {
  using hal::DriveState;
  if ((statusword & 0x4F) == 0x00) return DriveState::kNotReadyToSwitchOn;
  if ((statusword & 0x4F) == 0x40) return DriveState::kSwitchOnDisabled;
  if ((statusword & 0x6F) == 0x21) return DriveState::kReadyToSwitchOn;
  if ((statusword & 0x6F) == 0x23) return DriveState::kSwitchedOn;
  if ((statusword & 0x6F) == 0x27) return DriveState::kOperationEnabled;
  if ((statusword & 0x6F) == 0x07) return DriveState::kQuickStopActive;
  if ((statusword & 0x4F) == 0x0F) return DriveState::kFaultReactionActive;
  if ((statusword & 0x4F) == 0x08) return DriveState::kFault;
  // Patterns the table leaves undefined: report the safe reading.
  return DriveState::kNotReadyToSwitchOn;
}

/// The state bits of a statusword for `state` (voltage enabled while powered, remote set).
constexpr std::uint16_t statusword_of(hal::DriveState state) {
  using hal::DriveState;
  switch (state) {
    case DriveState::kNotReadyToSwitchOn:
      return 0x0000;
    case DriveState::kSwitchOnDisabled:
      return 0x0040;
    case DriveState::kReadyToSwitchOn:
      return 0x0021;
    case DriveState::kSwitchedOn:
      return 0x0023 | kStatusVoltageEnabled;
    case DriveState::kOperationEnabled:
      return 0x0027 | kStatusVoltageEnabled;
    case DriveState::kQuickStopActive:
      return 0x0007 | kStatusVoltageEnabled;
    case DriveState::kFaultReactionActive:
      return 0x000F;
    case DriveState::kFault:
      return 0x0008;
  }
  return 0x0000;
}

/// Device control commands (CiA 402-2 Table 29), as a controlword carries them.
enum class Command : std::uint8_t {
  kNone,             ///< A pattern that commands nothing new.
  kShutdown,         ///< 0bx..x110: transitions 2, 6, 8.
  kSwitchOn,         ///< 0bx..0111: transition 3 (and 5 from operation enabled).
  kEnableOperation,  ///< 0bx..1111: transitions 4, 16 (and 3+4 from ready to switch on).
  kDisableVoltage,   ///< 0bx..xx0x: transitions 7, 9, 10, 12.
  kQuickStop,        ///< 0bx..x01x: transitions 7, 10, 11.
  kFaultReset,       ///< Rising edge of bit 7: transition 15.
};

// Controlwords the master sends.
inline constexpr std::uint16_t kControlShutdown = 0x0006;
inline constexpr std::uint16_t kControlSwitchOn = 0x0007;
inline constexpr std::uint16_t kControlEnableOperation = 0x000F;
inline constexpr std::uint16_t kControlDisableVoltage = 0x0000;
inline constexpr std::uint16_t kControlQuickStop = 0x0002;
inline constexpr std::uint16_t kControlFaultReset = 0x0080;

/// What a controlword commands, given the previous one (fault reset acts on bit 7's rising edge).
constexpr Command decode_controlword(std::uint16_t controlword, std::uint16_t previous) {
  if ((controlword & 0x80) != 0 && (previous & 0x80) == 0) return Command::kFaultReset;
  if ((controlword & 0x80) != 0) return Command::kNone;  // Held reset bit: no new command.
  if ((controlword & 0x02) == 0) return Command::kDisableVoltage;
  if ((controlword & 0x06) == 0x02) return Command::kQuickStop;
  if ((controlword & 0x07) == 0x06) return Command::kShutdown;
  if ((controlword & 0x0F) == 0x07) return Command::kSwitchOn;
  if ((controlword & 0x0F) == 0x0F) return Command::kEnableOperation;
  return Command::kNone;
}

/// The drive side's state machine (CiA 402-2 Figure 4) for one command; the automatic
/// transitions (0, 1, 13, 14) are the drive's own business. Unaccepted commands keep the state.
constexpr hal::DriveState drive_state_after(hal::DriveState state, Command command) {
  using hal::DriveState;
  switch (command) {
    case Command::kShutdown:
      switch (state) {
        case DriveState::kSwitchOnDisabled:  // 2
        case DriveState::kSwitchedOn:        // 6
        case DriveState::kOperationEnabled:  // 8
          return DriveState::kReadyToSwitchOn;
        default:
          return state;
      }
    case Command::kSwitchOn:
      switch (state) {
        case DriveState::kReadyToSwitchOn:   // 3
        case DriveState::kOperationEnabled:  // 5
          return DriveState::kSwitchedOn;
        default:
          return state;
      }
    case Command::kEnableOperation:
      switch (state) {
        case DriveState::kReadyToSwitchOn:  // 3 + 4, as most drives accept
        case DriveState::kSwitchedOn:       // 4
        case DriveState::kQuickStopActive:  // 16
          return DriveState::kOperationEnabled;
        default:
          return state;
      }
    case Command::kDisableVoltage:
      switch (state) {
        case DriveState::kReadyToSwitchOn:   // 7
        case DriveState::kSwitchedOn:        // 10
        case DriveState::kOperationEnabled:  // 9
        case DriveState::kQuickStopActive:   // 12
          return DriveState::kSwitchOnDisabled;
        default:
          return state;
      }
    case Command::kQuickStop:
      switch (state) {
        case DriveState::kReadyToSwitchOn:  // 7
        case DriveState::kSwitchedOn:       // 10
          return DriveState::kSwitchOnDisabled;
        case DriveState::kOperationEnabled:  // 11
          return DriveState::kQuickStopActive;
        default:
          return state;
      }
    case Command::kFaultReset:
      return state == DriveState::kFault ? DriveState::kSwitchOnDisabled : state;  // 15
    case Command::kNone:
      return state;
  }
  return state;
}

/// The controlword a master sends to move a drive in `state` one step towards what `request`
/// asks. `previous` is the controlword sent last cycle: a fault reset needs bit 7 low first, then
/// high (the drive acts on the edge).
constexpr std::uint16_t controlword_toward(hal::DriveState state, hal::DriveRequest request,
                                           std::uint16_t previous) {
  using hal::DriveRequest;
  using hal::DriveState;
  switch (request) {
    case DriveRequest::kEnable:
      switch (state) {
        case DriveState::kSwitchOnDisabled:
          return kControlShutdown;
        case DriveState::kReadyToSwitchOn:
          return kControlSwitchOn;
        case DriveState::kSwitchedOn:
        case DriveState::kOperationEnabled:
        case DriveState::kQuickStopActive:
          return kControlEnableOperation;
        default:
          return kControlDisableVoltage;  // Booting or faulted: wait (a fault needs a reset).
      }
    case DriveRequest::kDisable:
      return kControlDisableVoltage;
    case DriveRequest::kQuickStop:
      return state == DriveState::kOperationEnabled || state == DriveState::kQuickStopActive
                 ? kControlQuickStop
                 : kControlDisableVoltage;
    case DriveRequest::kFaultReset:
      if (state != DriveState::kFault) return kControlDisableVoltage;
      return (previous & kControlFaultReset) != 0
                 ? kControlFaultReset  // Keep the bit high.
                 : ((previous == kControlDisableVoltage) ? kControlFaultReset
                                                         : kControlDisableVoltage);

    case DriveRequest::kHome:
      // Never a drive's standing request: homing_sequencer.hpp writes its own controlwords.
      return kControlDisableVoltage;
  }
  return kControlDisableVoltage;
}

/// Joint <-> drive units: the drive counts motor encoder counts; the joint turns once per
/// `gear_ratio` motor turns.
struct Units {
  double counts_per_rad = 1.0;

  static Units from(double gear_ratio, std::int64_t encoder_counts_per_rev) {
    return {gear_ratio * static_cast<double>(encoder_counts_per_rev) / (2.0 * std::numbers::pi)};
  }
  /// Rounded to the nearest count; saturates at the INTEGER32 range.
  std::int32_t to_counts(double rad) const {
    const double counts = std::round(rad * counts_per_rad);
    if (!(counts > -2147483648.0)) return INT32_MIN;
    if (!(counts < 2147483647.0)) return INT32_MAX;
    return static_cast<std::int32_t>(counts);
  }
  double to_rad(std::int32_t counts) const { return static_cast<double>(counts) / counts_per_rad; }
};

}  // namespace cambio::canopen::cia402
