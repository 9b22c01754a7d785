#pragma once

#include <cstdint>
#include <string_view>

namespace cambio::hal {

/// The power state of one joint's drive, one-to-one with the CiA 402 state machine (IEC
/// 61800-7-201, Figure 4 of CiA 402-2), so a CANopen backend maps statusword to state with no
/// loss and every other backend (the sim) follows the same rules.
enum class DriveState : std::uint8_t {
  kNotReadyToSwitchOn,   ///< Booting; no request is accepted yet.
  kSwitchOnDisabled,     ///< Powered down, ready to be asked to switch on (state after boot).
  kReadyToSwitchOn,      ///< "Shutdown" received; power stage may be charged.
  kSwitchedOn,           ///< Power stage on, motor not torqued.
  kOperationEnabled,     ///< Torqued, following targets. The only state in which a joint moves.
  kQuickStopActive,      ///< Braking to standstill on the quick-stop ramp, then holding.
  kFaultReactionActive,  ///< A fault was detected; the drive is braking before it opens.
  kFault,                ///< Latched fault: no torque until a fault reset.
};

/// What the layers above ask a drive to do. Requests are non-blocking: the joint group records
/// them and the resulting state shows on later read()s (a CiA 402 drive answers over the bus
/// in a cycle or more; the sim after a transition time).
enum class DriveRequest : std::uint8_t {
  kEnable,      ///< To operation enabled, through every intermediate state; holds the measured
                ///< position on arrival (never jumps to an old target).
  kDisable,     ///< To switch-on disabled (torque off).
  kQuickStop,   ///< Brake on the quick-stop ramp and hold (quick stop active).
  kFaultReset,  ///< Clear a latched fault: fault -> switch-on disabled (re-enable separately).
  /// Run the drive's homing (a joint whose encoder reference is not absolute). For one joint:
  /// home it again, refused (kRejected) if it does not home; for every joint: home those that
  /// must and have not since their drive booted. Homing ends disabled at the homed position; the
  /// standing enable request then enables it there. Joints that never home ignore it.
  kHome,
};

constexpr bool is_enabled(DriveState state) {
  return state == DriveState::kOperationEnabled;
}

constexpr bool is_faulted(DriveState state) {
  return state == DriveState::kFault || state == DriveState::kFaultReactionActive;
}

constexpr std::string_view to_string(DriveState state) {
  switch (state) {
    case DriveState::kNotReadyToSwitchOn:
      return "not ready to switch on";
    case DriveState::kSwitchOnDisabled:
      return "switch on disabled";
    case DriveState::kReadyToSwitchOn:
      return "ready to switch on";
    case DriveState::kSwitchedOn:
      return "switched on";
    case DriveState::kOperationEnabled:
      return "operation enabled";
    case DriveState::kQuickStopActive:
      return "quick stop active";
    case DriveState::kFaultReactionActive:
      return "fault reaction active";
    case DriveState::kFault:
      return "fault";
  }
  return "unknown";
}

constexpr std::string_view to_string(DriveRequest request) {
  switch (request) {
    case DriveRequest::kEnable:
      return "enable";
    case DriveRequest::kDisable:
      return "disable";
    case DriveRequest::kQuickStop:
      return "quick stop";
    case DriveRequest::kFaultReset:
      return "fault reset";
    case DriveRequest::kHome:
      return "home";
  }
  return "unknown";
}

/// The next state of a CiA 402 drive that receives `request` in `state`, one transition at a
/// time (what a master walks through by writing controlwords). Returns `state` when the request
/// is already satisfied or is not accepted in that state (e.g. enable while faulted: a fault
/// needs a reset first). Used by the sim's drive and by the CiA 402 master to plan a path.
constexpr DriveState next_drive_state(DriveState state, DriveRequest request) {
  switch (request) {
    case DriveRequest::kEnable:
      switch (state) {
        case DriveState::kSwitchOnDisabled:
          return DriveState::kReadyToSwitchOn;  // Transition 2 (shutdown).
        case DriveState::kReadyToSwitchOn:
          return DriveState::kSwitchedOn;  // Transition 3 (switch on).
        case DriveState::kSwitchedOn:
          return DriveState::kOperationEnabled;  // Transition 4 (enable operation).
        case DriveState::kQuickStopActive:
          return DriveState::kOperationEnabled;  // Transition 16.
        default:
          return state;
      }
    case DriveRequest::kDisable:
      switch (state) {
        case DriveState::kReadyToSwitchOn:
        case DriveState::kSwitchedOn:
        case DriveState::kOperationEnabled:
        case DriveState::kQuickStopActive:
          return DriveState::kSwitchOnDisabled;  // Transitions 7, 10, 9, 12 (disable voltage).
        default:
          return state;
      }
    case DriveRequest::kQuickStop:
      return state == DriveState::kOperationEnabled ? DriveState::kQuickStopActive  // 11.
                                                    : state;
    case DriveRequest::kFaultReset:
      return state == DriveState::kFault ? DriveState::kSwitchOnDisabled : state;  // 15.
    case DriveRequest::kHome:
      return state;  // A sequence of its own (mode 6), not a state transition.
  }
  return state;
}

}  // namespace cambio::hal
