// The emulated drive's homing mode (CiA 402-2 §12, modes of operation 6). Controlword bit 4's
// rising edge, in operation enabled, starts the method in 0x6098; the servo model moves the joint
// at the homing speeds (0x6099:1 towards the switch, 0x6099:2 for the edge or the index pulse)
// with its own acceleration limit; each servo step checks the switch and the index pulse:
//   17 (18): towards the negative (positive) limit switch at the switch speed, then back off it
//            at the zero speed; home is the switch's edge.
//   33 (34): in the negative (positive) direction at the zero speed; home is the first index
//            pulse crossed.
//   35, 37:  home is where the joint stands.
// The home position is latched where the edge or pulse is (as a drive's capture input does),
// and the joint then stops and returns onto it. Reaching the joint's limit before the switch is
// a homing error. Statusword bits 13/12/10 as cia402.hpp's table.

#include <cmath>
#include <numbers>

#include "emulated_drive_detail.hpp"

namespace cambio::virtual_rig {

using namespace emulated_drive_detail;

namespace {

bool is_limit_switch_method(std::int8_t method) {
  return method == 17 || method == 18;
}

/// The switch of `method` (17: negative, active at and below it; 18: positive, at and above).
bool switch_active(std::int8_t method, const std::optional<double>& switch_rad, double joint_rad) {
  if (!switch_rad) return false;
  return method == 17 ? joint_rad <= *switch_rad : joint_rad >= *switch_rad;
}

}  // namespace

bool EmulatedDrive::homing_method_supported(std::int8_t method) noexcept {
  // 0: no homing method chosen (the default).
  return method == 0 || method == 17 || method == 18 || method == 33 || method == 34 ||
         method == 35 || method == 37;
}

void EmulatedDrive::start_homing() noexcept {
  const auto method = static_cast<std::int8_t>(homing_method_->value);
  const double joint_rad = servo_.output_position_rad();
  homing_last_rad_ = joint_rad;
  const double switch_speed_rad_s =
      static_cast<double>(homing_switch_speed_->value) / units_.counts_per_rad;
  const double zero_speed_rad_s =
      static_cast<double>(homing_zero_speed_->value) / units_.counts_per_rad;
  switch (method) {
    case 17:
    case 18: {
      const double towards_switch = method == 17 ? -1.0 : 1.0;
      if (switch_active(method, config_.home_switch_rad, joint_rad)) {
        // Started on the switch: straight to backing off it.
        homing_phase_ = HomingPhase::kEdge;
        homing_direction_ = -towards_switch;
        (void)servo_.command({hal::CommandMode::kVelocity, -towards_switch * zero_speed_rad_s});
      } else {
        homing_phase_ = HomingPhase::kSearch;
        homing_direction_ = towards_switch;
        (void)servo_.command({hal::CommandMode::kVelocity, towards_switch * switch_speed_rad_s});
      }
      break;
    }
    case 33:
    case 34:
      homing_phase_ = HomingPhase::kEdge;
      homing_direction_ = method == 33 ? -1.0 : 1.0;
      (void)servo_.command({hal::CommandMode::kVelocity, homing_direction_ * zero_speed_rad_s});
      break;
    case 35:
    case 37:
      home_found(joint_rad);
      break;
    default:
      homing_phase_ = HomingPhase::kError;  // No method chosen (0x6098 = 0).
      break;
  }
  update_actual_values();
}

void EmulatedDrive::home_found(double home_rad) noexcept {
  home_rad_ = home_rad;
  // CiA 402-2, 0x607C: "once homing is completed, the zero position is offset from the home
  // position by adding the home offset to the home position": zero = home + offset, so the home
  // position reads -offset in the drive's new frame.
  origin_rad_ = home_rad + static_cast<double>(home_offset_->as_integer()) / units_.counts_per_rad;
  demand_rad_ = home_rad;
  homing_phase_ = HomingPhase::kToHome;
  (void)servo_.command({hal::CommandMode::kPosition, home_rad});
}

void EmulatedDrive::step_homing() noexcept {
  const auto method = static_cast<std::int8_t>(homing_method_->value);
  const double joint_rad = servo_.output_position_rad();
  const double previous_rad = homing_last_rad_;
  homing_last_rad_ = joint_rad;
  const sim::ServoParams& limits = servo_.params();
  // The noise-free profile: it stops exactly on the limit (the servo model clamps it there).
  const double profile_rad = servo_.state().profile_position_rad;
  const bool at_limit = homing_direction_ < 0.0 ? profile_rad <= limits.min_position_rad + 1e-9
                                                : profile_rad >= limits.max_position_rad - 1e-9;
  switch (homing_phase_) {
    case HomingPhase::kSearch:
      if (switch_active(method, config_.home_switch_rad, joint_rad)) {
        homing_phase_ = HomingPhase::kEdge;
        homing_direction_ = -homing_direction_;
        const double zero_speed_rad_s =
            static_cast<double>(homing_zero_speed_->value) / units_.counts_per_rad;
        (void)servo_.command({hal::CommandMode::kVelocity, homing_direction_ * zero_speed_rad_s});
      } else if (at_limit) {
        homing_phase_ = HomingPhase::kError;
        servo_.brake_to_stop();
      }
      return;
    case HomingPhase::kEdge:
      if (is_limit_switch_method(method)) {
        if (!switch_active(method, config_.home_switch_rad, joint_rad)) {
          home_found(*config_.home_switch_rad);
          return;
        }
      } else {
        // Index pulses at index_pulse_rad + k * pitch: a crossing changes k = floor(...).
        const double pitch_rad = 2.0 * std::numbers::pi / config_.gear_ratio;
        const double before = std::floor((previous_rad - config_.index_pulse_rad) / pitch_rad);
        const double now = std::floor((joint_rad - config_.index_pulse_rad) / pitch_rad);
        if (now != before) {
          home_found(config_.index_pulse_rad +
                     (homing_direction_ < 0.0 ? before : now) * pitch_rad);
          return;
        }
      }
      if (at_limit) {
        homing_phase_ = HomingPhase::kError;
        servo_.brake_to_stop();
      }
      return;
    case HomingPhase::kToHome: {
      const double window_rad =
          static_cast<double>(position_window_->value) / units_.counts_per_rad;
      if (servo_.at_rest() && std::abs(joint_rad - home_rad_) <= window_rad) {
        homing_phase_ = HomingPhase::kAttained;
      }
      return;
    }
    case HomingPhase::kIdle:
    case HomingPhase::kAttained:
    case HomingPhase::kError:
      return;
  }
}

std::uint16_t EmulatedDrive::homing_status_bits() const noexcept {
  switch (homing_phase_) {
    case HomingPhase::kIdle:
      return cia402::kStatusTargetReached;  // Not started or interrupted.
    case HomingPhase::kSearch:
    case HomingPhase::kEdge:
      return 0;  // In progress.
    case HomingPhase::kToHome:
      return cia402::kStatusHomingAttained;
    case HomingPhase::kAttained:
      return cia402::kStatusHomingAttained | cia402::kStatusTargetReached;
    case HomingPhase::kError:
      return cia402::kStatusHomingError | (servo_.at_rest() ? cia402::kStatusTargetReached : 0);
  }
  return 0;
}

}  // namespace cambio::virtual_rig
