#include "cambio/virtual_rig/emulated_drive.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "cambio/canopen/pdo_layout.hpp"
#include "emulated_drive_detail.hpp"

namespace cambio::virtual_rig {

using namespace emulated_drive_detail;

EmulatedDrive::EmulatedDrive(EmulatedDriveConfig config, hal::CanBus& bus)
    : config_(std::move(config)),
      bus_(bus),
      units_(cia402::Units::from(config_.gear_ratio, config_.encoder_counts_per_rev)),
      sdo_(config_.node_id, *this),
      servo_(config_.servo, config_.seed, config_.initial_position_rad) {
  if (config_.node_id < canopen::kMinNodeId || config_.node_id > canopen::kMaxNodeId) {
    throw std::invalid_argument("emulated drive: node id " + std::to_string(config_.node_id) +
                                " outside 1..127");
  }
  if (!(config_.gear_ratio > 0.0) || config_.encoder_counts_per_rev <= 0) {
    throw std::invalid_argument("emulated drive " + std::to_string(config_.node_id) +
                                ": gear ratio and encoder counts per rev must be positive");
  }
  if (!(config_.servo.step_s > 0.0)) {
    throw std::invalid_argument("emulated drive: servo step must be positive");
  }
  step_ns_ = std::max<std::int64_t>(1, std::llround(config_.servo.step_s * 1e9));
  build_dictionary();
  rebuild_pdos();
}

// --- NMT -------------------------------------------------------------------------------------

void EmulatedDrive::power_on(std::int64_t now_ns) noexcept {
  powered_ = true;
  now_ns_ = now_ns;
  power_on_ns_ = now_ns;
  first_enabled_ns_ = -1;
  servo_time_ns_ = now_ns;
  // A power cycle: every object back to its default, the home reference gone.
  dictionary_.restore_defaults(0x0000, 0xFFFF);
  following_error_ = false;
  previous_controlword_ = 0;
  origin_rad_ = 0.0;
  homing_phase_ = HomingPhase::kIdle;
  drive_state_ = DriveState::kNotReadyToSwitchOn;
  enter(DriveState::kSwitchOnDisabled);  // Transitions 0 and 1: self-test passed.
  boot(now_ns);
}

void EmulatedDrive::boot(std::int64_t now_ns) noexcept {
  sdo_.reset();
  rebuild_pdos();
  late_count_ = 0;
  // Boot-up: the heartbeat COB-ID with state 0 (CiA 301 §7.2.8.3.2.2), then pre-operational.
  nmt_state_ = NmtState::kBootUp;
  hal::CanFrame frame;
  frame.id = canopen::heartbeat_cob_id(config_.node_id);
  frame.length = 1;
  frame.data[0] = static_cast<std::uint8_t>(NmtState::kBootUp);
  send(frame);
  nmt_state_ = NmtState::kPreOperational;
  next_heartbeat_ns_ = now_ns + static_cast<std::int64_t>(heartbeat_time_->value) * 1'000'000;
  update_actual_values();
}

void EmulatedDrive::handle_nmt(const hal::CanFrame& frame, std::int64_t now_ns) noexcept {
  if (frame.length != 2) {
    ++counters_.malformed_frames;
    return;
  }
  const int target = frame.data[1];
  if (target != 0 && target != config_.node_id) return;
  switch (static_cast<canopen::NmtCommand>(frame.data[0])) {
    case canopen::NmtCommand::kStart:
      if (nmt_state_ != NmtState::kOperational) {
        nmt_state_ = NmtState::kOperational;
        rebuild_pdos();  // Fresh SYNC counters, no RPDO data from before.
      }
      return;
    case canopen::NmtCommand::kStop:
      nmt_state_ = NmtState::kStopped;
      sdo_.reset();
      return;
    case canopen::NmtCommand::kEnterPreOperational:
      nmt_state_ = NmtState::kPreOperational;
      return;
    case canopen::NmtCommand::kResetNode:
      // The application too: every object to its default, the drive back to switch on disabled
      // (a latched fault is cleared by the reset), the servo braking or holding.
      dictionary_.restore_defaults(0x0000, 0xFFFF);
      following_error_ = false;
      previous_controlword_ = 0;
      origin_rad_ = 0.0;
      homing_phase_ = HomingPhase::kIdle;
      drive_state_ = DriveState::kNotReadyToSwitchOn;
      enter(DriveState::kSwitchOnDisabled);
      boot(now_ns);
      return;
    case canopen::NmtCommand::kResetCommunication:
      dictionary_.restore_defaults(0x1000, 0x1FFF);
      boot(now_ns);
      return;
  }
  ++counters_.malformed_frames;  // Not a command CiA 301 defines.
}

// --- frames ------------------------------------------------------------------------------------

void EmulatedDrive::handle(const hal::CanFrame& frame, std::int64_t now_ns) noexcept {
  if (!powered_ || frame.error_frame || frame.extended_id) return;
  now_ns_ = now_ns;
  advance_servo(now_ns);
  if (frame.id == canopen::kNmtCobId) {
    handle_nmt(frame, now_ns);
    return;
  }
  if (nmt_state_ == NmtState::kStopped) return;  // Only NMT and heartbeat while stopped.
  if (frame.id == (sync_cob_id_->value & 0x7FFu)) {
    if (frame.length > 1 || frame.remote_request) {
      ++counters_.malformed_frames;
      return;
    }
    handle_sync(now_ns);
    return;
  }
  if (frame.id == canopen::sdo_request_cob_id(config_.node_id)) {
    if (frame.length != 8) {
      ++counters_.malformed_frames;  // CiA 301: SDO frames are always 8 bytes.
      return;
    }
    hal::CanFrame response;
    if (sdo_.handle(frame, response)) send(response);
    return;
  }
  if (nmt_state_ != NmtState::kOperational || frame.remote_request) return;
  for (int n = 0; n < kPdoCount; ++n) {
    const Pdo& pdo = rpdos_[static_cast<std::size_t>(n)];
    if (pdo.valid && pdo.cob_id == frame.id) handle_rpdo(n, frame);
  }
}

void EmulatedDrive::handle_sync(std::int64_t now_ns) noexcept {
  ++counters_.syncs;
  // Following error: the demand of the cycle that just ended against where the joint is.
  if (hal::is_enabled(drive_state_) && mode_->value == 8 &&
      following_window_->value != kFollowingErrorOff) {
    const double error_counts =
        std::abs(demand_rad_ - servo_.encoder_position_rad()) * units_.counts_per_rad;
    if (error_counts > static_cast<double>(following_window_->value)) {
      following_error_ = true;
      raise_fault(kEmcyFollowingError, 0);
    }
  }
  if (error_passive_syncs_left_ > 0 && --error_passive_syncs_left_ == 0) {
    error_register_->value &= ~static_cast<std::uint32_t>(kErrorCommunication);
    if (!hal::is_faulted(drive_state_)) {
      error_register_->value = 0;
      send_emergency(kEmcyErrorReset);  // Back to error active.
    }
  }
  update_actual_values();
  if (nmt_state_ == NmtState::kOperational) send_tpdos(now_ns);
  // Targets received during the last cycle take effect now, for the next one.
  for (Pdo& pdo : rpdos_) {
    if (pdo.valid && pdo.has_pending) {
      pdo.has_pending = false;
      apply_rpdo(pdo, std::span<const std::uint8_t>(pdo.pending.data(), pdo.bytes));
    }
  }
  latch_targets();
}

// --- SDO target ------------------------------------------------------------------------------

std::uint32_t EmulatedDrive::sdo_read(ObjectAddress address, std::span<std::uint8_t> out,
                                      std::size_t& size) {
  return dictionary_.read(address, out, size);
}

std::size_t EmulatedDrive::sdo_size(ObjectAddress address) const {
  const ObjectEntry* entry = dictionary_.find(address);
  return entry != nullptr ? entry->size() : 0;
}

std::uint32_t EmulatedDrive::sdo_write(ObjectAddress address, std::span<const std::uint8_t> data) {
  if (const std::uint32_t abort = dictionary_.check_write(address, data)) return abort;
  if (const std::uint32_t abort = check_pdo_write(address, data)) return abort;
  const std::uint32_t value = canopen::get_le(data, 0, data.size());
  if (address == ObjectAddress{canopen::kCobIdSync, 0} && (value & 0x6000'0000u) != 0) {
    return code(SdoAbortCode::kInvalidValue);  // Not a SYNC producer; no 29-bit ids.
  }
  if (address == cia402::kModesOfOperation) {
    const auto mode = static_cast<std::int8_t>(value);
    if (mode != 6 && mode != 8 && mode != 9) return code(SdoAbortCode::kInvalidValue);
  }
  if (address == cia402::kHomingMethod &&
      !homing_method_supported(static_cast<std::int8_t>(value))) {
    return code(SdoAbortCode::kInvalidValue);  // As a drive without that method answers.
  }
  const std::uint32_t previous_mode = mode_->value;
  (void)dictionary_.write(address, data);
  const std::uint16_t index = address.index;
  if (in(index, canopen::kRpdoCommunication) || in(index, canopen::kTpdoCommunication) ||
      in(index, canopen::kRpdoMapping) || in(index, canopen::kTpdoMapping)) {
    rebuild_pdos();
  } else if (index == canopen::kProducerHeartbeatTime) {
    next_heartbeat_ns_ = now_ns_ + static_cast<std::int64_t>(value) * 1'000'000;
  } else if (address == cia402::kControlword) {
    on_controlword(static_cast<std::uint16_t>(value));
  } else if (address == cia402::kModesOfOperation) {
    if (previous_mode != mode_->value && hal::is_enabled(drive_state_)) enter(drive_state_);
  } else if (address == cia402::kTargetPosition || address == cia402::kTargetVelocity ||
             address == cia402::kVelocityOffset || address == cia402::kTorqueOffset) {
    targets_written_ = targets_written_ || hal::is_enabled(drive_state_);
  }
  update_actual_values();
  return 0;
}

// --- CiA 402 -------------------------------------------------------------------------------

void EmulatedDrive::on_controlword(std::uint16_t controlword) noexcept {
  const cia402::Command command = cia402::decode_controlword(controlword, previous_controlword_);
  const bool homing_bit = (controlword & cia402::kControlHomingStart) != 0;
  const bool homing_bit_before = (previous_controlword_ & cia402::kControlHomingStart) != 0;
  previous_controlword_ = controlword;
  const DriveState next = cia402::drive_state_after(drive_state_, command);
  if (next != drive_state_) {
    if (drive_state_ == DriveState::kFault) {
      // Transition 15: the fault is cleared and the drive says so (EMCY 0x0000).
      following_error_ = false;
      error_code_->value = 0;
      error_register_->value = 0;
      send_emergency(kEmcyErrorReset);
    }
    enter(next);
  }
  if (mode_->value != 6 || !hal::is_enabled(drive_state_) || homing_bit == homing_bit_before) {
    return;
  }
  if (homing_bit) {
    start_homing();
  } else if (homing_phase_ == HomingPhase::kSearch || homing_phase_ == HomingPhase::kEdge ||
             homing_phase_ == HomingPhase::kToHome) {
    homing_phase_ = HomingPhase::kIdle;  // Bit 4 cleared: interrupted.
    servo_.brake_to_stop();
    update_actual_values();
  }
}

void EmulatedDrive::enter(DriveState state) noexcept {
  drive_state_ = state;
  // A state or mode change ends a homing run that has not completed.
  if (homing_phase_ != HomingPhase::kAttained && homing_phase_ != HomingPhase::kError) {
    homing_phase_ = HomingPhase::kIdle;
  }
  if (state == DriveState::kOperationEnabled && first_enabled_ns_ < 0) first_enabled_ns_ = now_ns_;
  targets_written_ = false;
  const double measured_rad = servo_.output_position_rad();
  // As the sim's drives: enabled, or stopped, hold where the joint is (never jump to an old
  // target); still moving, brake on the acceleration limit, then hold where it stopped.
  if (state == DriveState::kOperationEnabled) {
    servo_.hold_at(measured_rad);
    demand_rad_ = servo_.output_position_rad();
  } else if (state == DriveState::kQuickStopActive || state == DriveState::kFaultReactionActive ||
             !servo_.at_rest()) {
    servo_.brake_to_stop();
  } else {
    servo_.hold_at(measured_rad);
  }
  update_actual_values();
}

void EmulatedDrive::latch_targets() noexcept {
  // Homing ignores the cyclic targets.
  if (!hal::is_enabled(drive_state_) || !targets_written_ || mode_->value == 6) return;
  const double torque_nm =
      static_cast<double>(torque_offset_->as_integer()) / 1000.0 * config_.rated_torque_nm;
  if (mode_->value == 8) {
    const std::int64_t target = std::clamp(
        target_position_->as_integer(), min_position_->as_integer(), max_position_->as_integer());
    demand_rad_ = units_.to_rad(static_cast<std::int32_t>(target)) + origin_rad_;
    const double velocity_rad_s =
        static_cast<double>(velocity_offset_->as_integer()) / units_.counts_per_rad;
    (void)servo_.command({hal::CommandMode::kPosition, demand_rad_, velocity_rad_s, torque_nm});
  } else {
    const double max_counts_s = static_cast<double>(max_velocity_->value);
    const double velocity_counts_s = std::clamp(static_cast<double>(target_velocity_->as_integer()),
                                                -max_counts_s, max_counts_s);
    (void)servo_.command(
        {hal::CommandMode::kVelocity, velocity_counts_s / units_.counts_per_rad, 0.0, torque_nm});
  }
}

void EmulatedDrive::raise_fault(std::uint16_t error_code,
                                std::uint8_t error_register_bits) noexcept {
  error_code_->value = error_code;
  error_register_->value |= kErrorGeneric | error_register_bits;
  if (!hal::is_faulted(drive_state_)) enter(DriveState::kFaultReactionActive);
  send_emergency(error_code);
}

void EmulatedDrive::advance_servo(std::int64_t now_ns) noexcept {
  if (now_ns - servo_time_ns_ > kMaxCatchUpNs) servo_time_ns_ = now_ns - kMaxCatchUpNs;
  bool stepped = false;
  while (servo_time_ns_ + step_ns_ <= now_ns) {
    servo_.step();
    servo_.observe(servo_.output_position_rad());  // No physics here: the joint is the servo's.
    servo_time_ns_ += step_ns_;
    stepped = true;
    if (homing_phase_ != HomingPhase::kIdle && mode_->value == 6) step_homing();
    // Transition 14: the fault reaction ends when the joint stands still.
    if (drive_state_ == DriveState::kFaultReactionActive && servo_.at_rest()) {
      enter(DriveState::kFault);
    }
  }
  if (stepped) update_actual_values();
}

void EmulatedDrive::update_actual_values() noexcept {
  const std::int32_t actual_counts = units_.to_counts(to_drive_rad(servo_.encoder_position_rad()));
  position_actual_->value = static_cast<std::uint32_t>(actual_counts);
  velocity_actual_->value =
      static_cast<std::uint32_t>(units_.to_counts(servo_.encoder_velocity_rad_s()));
  const bool enabled = hal::is_enabled(drive_state_);
  const double torque_per_mille = enabled ? static_cast<double>(torque_offset_->as_integer()) : 0.0;
  torque_actual_->value =
      static_cast<std::uint32_t>(static_cast<std::int16_t>(torque_per_mille)) & 0xFFFFu;
  const std::int32_t demand_counts = units_.to_counts(to_drive_rad(demand_rad_));
  position_demand_->value = static_cast<std::uint32_t>(demand_counts);
  mode_display_->value = mode_->value;

  std::uint32_t status = cia402::statusword_of(drive_state_) | cia402::kStatusRemote;
  if (enabled && mode_->value == 6) {
    status |= homing_status_bits();
  } else if (enabled) {
    status |= cia402::kStatusDriveFollowsCommand;
    const bool settled = mode_->value == 8
                             ? std::abs(static_cast<std::int64_t>(demand_counts) - actual_counts) <=
                                   static_cast<std::int64_t>(position_window_->value)
                             : target_velocity_->value == 0;
    if (servo_.at_rest() && settled) status |= cia402::kStatusTargetReached;
  }
  if (drive_state_ == DriveState::kQuickStopActive && servo_.at_rest()) {
    status |= cia402::kStatusTargetReached;  // Halted on the quick-stop ramp.
  }
  if (following_error_) status |= cia402::kStatusFollowingError;
  if (error_passive_syncs_left_ > 0) status |= cia402::kStatusWarning;
  statusword_->value = status;
}

// --- emergencies, heartbeat, faults ---------------------------------------------------------

void EmulatedDrive::send_emergency(std::uint16_t error_code) noexcept {
  if (nmt_state_ != NmtState::kPreOperational && nmt_state_ != NmtState::kOperational) return;
  // [error code (2, LE)][error register][manufacturer-specific (5): 0]
  hal::CanFrame frame;
  frame.id = canopen::emcy_cob_id(config_.node_id);
  frame.length = 8;
  canopen::put_le(frame.data, 0, 2, error_code);
  frame.data[2] = static_cast<std::uint8_t>(error_register_->value);
  send(frame);
  ++counters_.emergencies;
}

void EmulatedDrive::send(const hal::CanFrame& frame) noexcept {
  if (bus_.send(frame) != hal::Status::kOk) ++counters_.send_failures;
}

void EmulatedDrive::poll(std::int64_t now_ns) noexcept {
  if (!powered_) return;
  now_ns_ = now_ns;
  advance_servo(now_ns);
  run_faults(now_ns);
  const auto period_ns = static_cast<std::int64_t>(heartbeat_time_->value) * 1'000'000;
  if (period_ns > 0 && now_ns >= next_heartbeat_ns_) {
    if (!heartbeat_stopped_) {
      hal::CanFrame frame;
      frame.id = canopen::heartbeat_cob_id(config_.node_id);
      frame.length = 1;
      frame.data[0] = static_cast<std::uint8_t>(nmt_state_);
      send(frame);
      ++counters_.heartbeats;
    }
    // Deadlines from the schedule, not from when this ran; a long stall does not burst.
    next_heartbeat_ns_ += period_ns;
    if (next_heartbeat_ns_ <= now_ns) next_heartbeat_ns_ = now_ns + period_ns;
  }
  std::size_t kept = 0;
  for (std::size_t k = 0; k < late_count_; ++k) {
    if (late_[k].due_ns <= now_ns) {
      send(late_[k].frame);
      ++counters_.tpdos_sent;
    } else {
      late_[kept++] = late_[k];
    }
  }
  late_count_ = kept;
}

std::int64_t EmulatedDrive::next_event_ns() const noexcept {
  std::int64_t next = INT64_MAX;
  if (!powered_) return next;
  if (heartbeat_time_->value > 0) next = std::min(next, next_heartbeat_ns_);
  for (std::size_t k = 0; k < late_count_; ++k) next = std::min(next, late_[k].due_ns);
  for (std::size_t k = 0; k < fault_count_; ++k) {
    if (!faults_[k].done) {
      next = std::min(next, due_ns(faults_[k].fault));
    }
  }
  return next;
}

std::int64_t EmulatedDrive::due_ns(const FaultInjection& fault) const noexcept {
  const std::int64_t base_ns = fault.after_enable ? first_enabled_ns_ : power_on_ns_;
  if (base_ns < 0) return INT64_MAX;  // Not enabled yet.
  return base_ns + std::llround(fault.at_s * 1e9);
}

bool EmulatedDrive::schedule(const FaultInjection& fault) noexcept {
  if (fault.node_id != 0 && fault.node_id != config_.node_id) return false;
  if (fault_count_ == kMaxScheduledFaults) return false;
  faults_[fault_count_++] = {fault, false};
  return true;
}

void EmulatedDrive::run_faults(std::int64_t now_ns) noexcept {
  for (std::size_t k = 0; k < fault_count_; ++k) {
    ScheduledFault& scheduled = faults_[k];
    if (scheduled.done || now_ns < due_ns(scheduled.fault)) {
      continue;
    }
    scheduled.done = true;
    const FaultInjection& fault = scheduled.fault;
    switch (fault.kind) {
      case FaultKind::kHeartbeatStop:
        heartbeat_stopped_ = true;
        break;
      case FaultKind::kEmergency:
        if (fault.latch_fault) {
          raise_fault(fault.emcy_code, 0);
        } else {
          const std::uint32_t saved = error_register_->value;
          error_register_->value = saved | kErrorGeneric;
          send_emergency(fault.emcy_code);
          error_register_->value = saved;
        }
        break;
      case FaultKind::kFollowingError:
        following_error_ = true;
        raise_fault(kEmcyFollowingError, 0);
        break;
      case FaultKind::kErrorFrames:
        error_passive_syncs_left_ = fault.count;
        error_register_->value |= kErrorGeneric | kErrorCommunication;
        send_emergency(kEmcyCanErrorPassive);
        update_actual_values();
        break;
      case FaultKind::kDropTpdo:
        tpdos_to_drop_ += fault.count;
        break;
      case FaultKind::kLateTpdo:
        tpdos_to_delay_ += fault.count;
        tpdo_delay_ns_ = std::llround(fault.delay_s * 1e9);
        break;
      case FaultKind::kSdoAbort:
        sdo_.inject_abort(fault.object, fault.abort_code);
        break;
    }
  }
}

}  // namespace cambio::virtual_rig
