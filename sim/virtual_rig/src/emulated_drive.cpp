#include "cambio/virtual_rig/emulated_drive.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "cambio/canopen/pdo_layout.hpp"

namespace cambio::virtual_rig {

namespace {

using canopen::NmtState;
using canopen::ObjectAddress;
using canopen::SdoAbortCode;
using hal::DriveState;
namespace cia402 = canopen::cia402;

constexpr std::uint32_t code(SdoAbortCode abort) {
  return static_cast<std::uint32_t>(abort);
}

constexpr std::int64_t kNsPerS = 1'000'000'000;
/// After a longer silence the servo skips ahead instead of replaying it step by step.
constexpr std::int64_t kMaxCatchUpNs = kNsPerS;

// Error register (0x1001) bits, CiA 301 Table 48.
constexpr std::uint8_t kErrorGeneric = 1u << 0;
constexpr std::uint8_t kErrorCommunication = 1u << 4;

// EMCY error codes (CiA 301 Table 21, CiA 402-2 Table 2).
constexpr std::uint16_t kEmcyErrorReset = 0x0000;
constexpr std::uint16_t kEmcyCanErrorPassive = 0x8120;
constexpr std::uint16_t kEmcyPdoLength = 0x8210;
constexpr std::uint16_t kEmcyFollowingError = 0x8611;

constexpr std::uint32_t kFollowingErrorOff = 0xFFFF'FFFF;

/// Supported drive modes (0x6502): bit 7 cyclic synchronous position, bit 8 velocity.
constexpr std::uint32_t kSupportedModes = (1u << 7) | (1u << 8);

bool in(std::uint16_t index, std::uint16_t first) {
  return index >= first && index < first + EmulatedDrive::kPdoCount;
}

std::uint32_t saturating_counts(double counts) {
  if (!(counts < 4294967295.0)) return 0xFFFF'FFFFu;
  return counts > 0.0 ? static_cast<std::uint32_t>(std::lround(counts)) : 0u;
}

}  // namespace

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

void EmulatedDrive::build_dictionary() {
  auto& d = dictionary_;
  const int id = config_.node_id;
  using enum DataType;
  using enum Access;
  d.add({canopen::kDeviceType, 0}, "Device type", kUnsigned32, kReadOnly,
        cia402::kDeviceTypeServoDrive);
  d.add({canopen::kErrorRegister, 0}, "Error register", kUnsigned8, kReadOnly, 0, true);
  d.add({canopen::kCobIdSync, 0}, "COB-ID SYNC", kUnsigned32, kReadWrite, canopen::kSyncCobId);
  d.add_string({canopen::kManufacturerDeviceName, 0}, "Manufacturer device name",
               "Cambio virtual CiA 402 drive");
  d.add({canopen::kProducerHeartbeatTime, 0}, "Producer heartbeat time", kUnsigned16, kReadWrite,
        static_cast<std::uint32_t>(std::lround(config_.heartbeat_period_s * 1000.0)));
  d.add({canopen::kIdentity, 0}, "Highest sub-index supported", kUnsigned8, kConst, 4);
  d.add({canopen::kIdentity, 1}, "Vendor-ID", kUnsigned32, kReadOnly, 0);
  d.add({canopen::kIdentity, 2}, "Product code", kUnsigned32, kReadOnly, 0x0000'0402);
  d.add({canopen::kIdentity, 3}, "Revision number", kUnsigned32, kReadOnly, 0x0001'0000);
  d.add({canopen::kIdentity, 4}, "Serial number", kUnsigned32, kReadOnly,
        static_cast<std::uint32_t>(id));

  // PDOs: by default the minimum set the stack's layout names (RPDO1 and TPDO1 valid).
  const canopen::PdoLayout layout = canopen::pdo_layout(config_.mode, hal::CanGroupSettings{});
  for (int n = 0; n < kPdoCount; ++n) {
    const auto i = static_cast<std::uint16_t>(n);
    const std::uint32_t invalid = n == 0 ? 0u : canopen::kPdoCobIdInvalid;
    d.add({static_cast<std::uint16_t>(canopen::kRpdoCommunication + i), 0},
          "Highest sub-index supported", kUnsigned8, kConst, 2);
    d.add({static_cast<std::uint16_t>(canopen::kRpdoCommunication + i), 1}, "COB-ID used by RPDO",
          kUnsigned32, kReadWrite, invalid | canopen::rpdo_cob_id(n + 1, id));
    d.add({static_cast<std::uint16_t>(canopen::kRpdoCommunication + i), 2}, "Transmission type",
          kUnsigned8, kReadWrite, canopen::kTransmissionSyncEvery);
    d.add({static_cast<std::uint16_t>(canopen::kTpdoCommunication + i), 0},
          "Highest sub-index supported", kUnsigned8, kConst, 2);
    d.add({static_cast<std::uint16_t>(canopen::kTpdoCommunication + i), 1}, "COB-ID used by TPDO",
          kUnsigned32, kReadWrite,
          invalid | canopen::kPdoCobIdNoRtr | canopen::tpdo_cob_id(n + 1, id));
    d.add({static_cast<std::uint16_t>(canopen::kTpdoCommunication + i), 2}, "Transmission type",
          kUnsigned8, kReadWrite, canopen::kTransmissionSyncEvery);
    const auto add_mapping = [&d](std::uint16_t index, const canopen::PdoMapping& mapping) {
      d.add({index, 0}, "Number of mapped objects", kUnsigned8, kReadWrite,
            static_cast<std::uint32_t>(mapping.count))
          .high = static_cast<std::int64_t>(kMaxMappedObjects);
      for (std::size_t k = 0; k < kMaxMappedObjects; ++k) {
        const std::uint32_t entry =
            k < mapping.count
                ? canopen::pdo_mapping_entry(mapping.entries[k].object, mapping.entries[k].bits)
                : 0u;
        d.add({index, static_cast<std::uint8_t>(k + 1)}, "Mapped object", kUnsigned32, kReadWrite,
              entry);
      }
    };
    add_mapping(static_cast<std::uint16_t>(canopen::kRpdoMapping + i),
                layout.rpdos[static_cast<std::size_t>(n)]);
    add_mapping(static_cast<std::uint16_t>(canopen::kTpdoMapping + i),
                layout.tpdos[static_cast<std::size_t>(n)]);
  }

  // CiA 402 objects.
  const auto counts = [this](double rad) {
    return static_cast<std::uint32_t>(units_.to_counts(rad));
  };
  d.add(cia402::kErrorCode, "Error code", kUnsigned16, kReadOnly, 0, true);
  d.add(cia402::kControlword, "Controlword", kUnsigned16, kReadWrite, 0, true);
  d.add(cia402::kStatusword, "Statusword", kUnsigned16, kReadOnly, 0, true);
  const auto mode = static_cast<std::uint32_t>(static_cast<std::uint8_t>(
      config_.mode == hal::CommandMode::kPosition ? cia402::Mode::kCyclicSynchronousPosition
                                                  : cia402::Mode::kCyclicSynchronousVelocity));
  d.add(cia402::kModesOfOperation, "Modes of operation", kInteger8, kReadWrite, mode, true);
  d.add(cia402::kModesOfOperationDisplay, "Modes of operation display", kInteger8, kReadOnly, mode,
        true);
  d.add(cia402::kPositionDemandValue, "Position demand value", kInteger32, kReadOnly, 0, true);
  d.add(cia402::kPositionActualValue, "Position actual value", kInteger32, kReadOnly, 0, true);
  d.add(cia402::kFollowingErrorWindow, "Following error window", kUnsigned32, kReadWrite,
        config_.following_error_window_rad > 0.0
            ? saturating_counts(config_.following_error_window_rad * units_.counts_per_rad)
            : kFollowingErrorOff);
  d.add({0x6067, 0}, "Position window", kUnsigned32, kReadWrite,
        saturating_counts(config_.position_window_rad * units_.counts_per_rad));
  d.add(cia402::kVelocityActualValue, "Velocity actual value", kInteger32, kReadOnly, 0, true);
  d.add(cia402::kRatedTorque, "Rated torque", kUnsigned32, kConst,
        saturating_counts(config_.rated_torque_nm * 1000.0));
  d.add(cia402::kTorqueActualValue, "Torque actual value", kInteger16, kReadOnly, 0, true);
  d.add(cia402::kTargetPosition, "Target position", kInteger32, kReadWrite, 0, true);
  d.add({cia402::kMinSoftwarePositionLimit.index, 0}, "Highest sub-index supported", kUnsigned8,
        kConst, 2);
  d.add(cia402::kMinSoftwarePositionLimit, "Min position limit", kInteger32, kReadWrite,
        counts(config_.servo.min_position_rad));
  d.add(cia402::kMaxSoftwarePositionLimit, "Max position limit", kInteger32, kReadWrite,
        counts(config_.servo.max_position_rad));
  d.add(cia402::kMaxProfileVelocity, "Max profile velocity", kUnsigned32, kReadWrite,
        saturating_counts(config_.servo.max_velocity_rad_s * units_.counts_per_rad));
  d.add(cia402::kVelocityOffset, "Velocity offset", kInteger32, kReadWrite, 0, true);
  d.add(cia402::kTorqueOffset, "Torque offset", kInteger16, kReadWrite, 0, true);
  d.add({cia402::kInterpolationTimePeriod.index, 0}, "Highest sub-index supported", kUnsigned8,
        kConst, 2);
  d.add(cia402::kInterpolationTimePeriod, "Interpolation time period value", kUnsigned8, kReadWrite,
        1);
  // CiA 402: the index is the power of ten of the period's unit, -128..63 (default ms).
  d.add(cia402::kInterpolationTimeIndex, "Interpolation time index", kInteger8, kReadWrite,
        static_cast<std::uint8_t>(-3))
      .high = 63;
  d.add(cia402::kTargetVelocity, "Target velocity", kInteger32, kReadWrite, 0, true);
  d.add(cia402::kSupportedDriveModes, "Supported drive modes", kUnsigned32, kReadOnly,
        kSupportedModes);
  d.finalise();

  controlword_ = d.find(cia402::kControlword);
  statusword_ = d.find(cia402::kStatusword);
  error_register_ = d.find({canopen::kErrorRegister, 0});
  error_code_ = d.find(cia402::kErrorCode);
  mode_ = d.find(cia402::kModesOfOperation);
  mode_display_ = d.find(cia402::kModesOfOperationDisplay);
  position_actual_ = d.find(cia402::kPositionActualValue);
  position_demand_ = d.find(cia402::kPositionDemandValue);
  velocity_actual_ = d.find(cia402::kVelocityActualValue);
  torque_actual_ = d.find(cia402::kTorqueActualValue);
  target_position_ = d.find(cia402::kTargetPosition);
  target_velocity_ = d.find(cia402::kTargetVelocity);
  velocity_offset_ = d.find(cia402::kVelocityOffset);
  torque_offset_ = d.find(cia402::kTorqueOffset);
  following_window_ = d.find(cia402::kFollowingErrorWindow);
  position_window_ = d.find({0x6067, 0});
  heartbeat_time_ = d.find({canopen::kProducerHeartbeatTime, 0});
  sync_cob_id_ = d.find({canopen::kCobIdSync, 0});
  min_position_ = d.find(cia402::kMinSoftwarePositionLimit);
  max_position_ = d.find(cia402::kMaxSoftwarePositionLimit);
  max_velocity_ = d.find(cia402::kMaxProfileVelocity);
}

// --- NMT -------------------------------------------------------------------------------------

void EmulatedDrive::power_on(std::int64_t now_ns) noexcept {
  powered_ = true;
  now_ns_ = now_ns;
  power_on_ns_ = now_ns;
  first_enabled_ns_ = -1;
  servo_time_ns_ = now_ns;
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

void EmulatedDrive::handle_rpdo(int n, const hal::CanFrame& frame) noexcept {
  Pdo& pdo = rpdos_[static_cast<std::size_t>(n)];
  if (frame.length < pdo.bytes) {
    // CiA 301: a PDO shorter than its mapping is not processed; EMCY 0x8210 says so.
    ++counters_.malformed_frames;
    const std::uint8_t saved = static_cast<std::uint8_t>(error_register_->value);
    error_register_->value = saved | kErrorGeneric | kErrorCommunication;
    send_emergency(kEmcyPdoLength);
    error_register_->value = saved;
    return;
  }
  ++counters_.rpdos;
  if (pdo.transmission_type <= 240) {
    std::copy_n(frame.data.begin(), pdo.bytes, pdo.pending.begin());
    pdo.has_pending = true;
  } else {
    apply_rpdo(pdo, std::span<const std::uint8_t>(frame.data.data(), pdo.bytes));
  }
}

void EmulatedDrive::apply_rpdo(const Pdo& pdo, std::span<const std::uint8_t> data) noexcept {
  std::size_t offset = 0;
  for (std::size_t k = 0; k < pdo.count; ++k) {
    const MappedEntry& mapped = pdo.entries[k];
    const std::uint32_t raw = canopen::get_le(data, offset, mapped.bytes);
    offset += mapped.bytes;
    ObjectEntry& entry = *mapped.entry;
    if (&entry == mode_) {
      const auto mode = static_cast<std::int8_t>(raw);
      if (mode != 8 && mode != 9) continue;  // Not a mode this drive has: keep the old one.
      const bool changed = mode_->value != raw;
      entry.value = raw;
      if (changed && hal::is_enabled(drive_state_)) enter(drive_state_);
      continue;
    }
    entry.value = raw;
    if (&entry == controlword_) {
      on_controlword(static_cast<std::uint16_t>(raw));
    } else if (&entry == target_position_ || &entry == target_velocity_ ||
               &entry == velocity_offset_ || &entry == torque_offset_) {
      targets_written_ = targets_written_ || hal::is_enabled(drive_state_);
    }
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

void EmulatedDrive::send_tpdos(std::int64_t now_ns) noexcept {
  for (Pdo& pdo : tpdos_) {
    if (!pdo.valid || pdo.count == 0) continue;
    if (pdo.transmission_type != 0 && ++pdo.sync_count < pdo.transmission_type) continue;
    pdo.sync_count = 0;
    hal::CanFrame frame;
    frame.id = pdo.cob_id;
    frame.length = static_cast<std::uint8_t>(pdo.bytes);
    std::size_t offset = 0;
    for (std::size_t k = 0; k < pdo.count; ++k) {
      canopen::put_le(frame.data, offset, pdo.entries[k].bytes, pdo.entries[k].entry->value);
      offset += pdo.entries[k].bytes;
    }
    if (pdo.transmission_type == 0 && pdo.sent_once &&
        std::equal(frame.data.begin(), frame.data.begin() + static_cast<long>(pdo.bytes),
                   pdo.last_sent.begin())) {
      continue;  // Acyclic synchronous: only when the data changed.
    }
    std::copy_n(frame.data.begin(), pdo.bytes, pdo.last_sent.begin());
    pdo.sent_once = true;
    if (tpdos_to_drop_ > 0) {
      --tpdos_to_drop_;
      ++counters_.tpdos_dropped;
      continue;
    }
    if (tpdos_to_delay_ > 0 && late_count_ < kMaxLateFrames) {
      --tpdos_to_delay_;
      ++counters_.tpdos_late;
      late_[late_count_++] = {frame, now_ns + tpdo_delay_ns_};
      continue;
    }
    send(frame);
    ++counters_.tpdos_sent;
  }
}

// --- PDO configuration ---------------------------------------------------------------------

std::uint32_t EmulatedDrive::check_mapping(bool receive, std::uint32_t mapping) const noexcept {
  if (mapping == 0) return 0;  // An unused entry.
  const ObjectAddress object = canopen::mapped_object(mapping);
  const ObjectEntry* entry = dictionary_.find(object);
  if (entry == nullptr) return dictionary_.missing_code(object);
  if (!entry->pdo_mappable) return code(SdoAbortCode::kCannotMapToPdo);
  if (receive ? !writable(entry->access) : !readable(entry->access)) {
    return code(SdoAbortCode::kCannotMapToPdo);
  }
  // Whole objects only: the entry's length must be the object's.
  if (static_cast<std::size_t>(canopen::mapped_bits(mapping)) != 8 * size_of(entry->type)) {
    return code(SdoAbortCode::kCannotMapToPdo);
  }
  return 0;
}

std::uint32_t EmulatedDrive::check_pdo_write(ObjectAddress address,
                                             std::span<const std::uint8_t> data) const noexcept {
  const std::uint16_t index = address.index;
  const bool rpdo_comm = in(index, canopen::kRpdoCommunication);
  const bool tpdo_comm = in(index, canopen::kTpdoCommunication);
  const bool rpdo_map = in(index, canopen::kRpdoMapping);
  const bool tpdo_map = in(index, canopen::kTpdoMapping);
  if (!rpdo_comm && !tpdo_comm && !rpdo_map && !tpdo_map) return 0;
  const std::uint32_t value = canopen::get_le(data, 0, data.size());
  if (rpdo_comm || tpdo_comm) {
    if (address.subindex == 1) {
      const std::uint32_t current = dictionary_.get(address);
      if ((value & 0x2000'0000u) != 0) return code(SdoAbortCode::kInvalidValue);  // 29-bit ids.
      const bool valid_now = (current & canopen::kPdoCobIdInvalid) == 0;
      const bool valid_next = (value & canopen::kPdoCobIdInvalid) == 0;
      // CiA 301: a valid PDO's COB-ID cannot change; invalidate it first.
      if (valid_now && valid_next && (value & 0x7FFu) != (current & 0x7FFu)) {
        return code(SdoAbortCode::kInvalidValue);
      }
      if (valid_next && (value & 0x7FFu) == 0) return code(SdoAbortCode::kInvalidValue);
    } else if (address.subindex == 2) {
      // RPDO: synchronous 0..240 or event 254/255. TPDO: synchronous only (1..240, 0 acyclic).
      const bool ok = value <= 240 || (rpdo_comm && value >= 254);
      if (!ok) return code(SdoAbortCode::kInvalidValue);
    }
    return 0;
  }
  const auto comm_index = static_cast<std::uint16_t>(
      index - (rpdo_map ? canopen::kRpdoMapping : canopen::kTpdoMapping) +
      (rpdo_map ? canopen::kRpdoCommunication : canopen::kTpdoCommunication));
  // CiA 301 §7.5.2.36: the mapping changes only while the PDO is invalid and, for the entries,
  // while sub 0 is 0.
  if ((dictionary_.get({comm_index, 1}) & canopen::kPdoCobIdInvalid) == 0) {
    return code(SdoAbortCode::kCannotTransferDeviceState);
  }
  if (address.subindex != 0) {
    if (dictionary_.get({index, 0}) != 0) return code(SdoAbortCode::kCannotTransferDeviceState);
    return check_mapping(rpdo_map, value);
  }
  int bits = 0;
  for (std::uint32_t k = 1; k <= value; ++k) {
    const std::uint32_t entry = dictionary_.get({index, static_cast<std::uint8_t>(k)});
    if (entry == 0) return code(SdoAbortCode::kCannotMapToPdo);
    if (const std::uint32_t abort = check_mapping(rpdo_map, entry)) return abort;
    bits += canopen::mapped_bits(entry);
  }
  if (bits > 64) return code(SdoAbortCode::kPdoLengthExceeded);
  return 0;
}

void EmulatedDrive::rebuild_pdos() noexcept {
  const auto build = [this](std::array<Pdo, kPdoCount>& pdos, std::uint16_t comm,
                            std::uint16_t map) {
    for (int n = 0; n < kPdoCount; ++n) {
      Pdo& pdo = pdos[static_cast<std::size_t>(n)];
      pdo = Pdo{};
      const auto comm_index = static_cast<std::uint16_t>(comm + n);
      const auto map_index = static_cast<std::uint16_t>(map + n);
      const std::uint32_t cob_id = dictionary_.get({comm_index, 1});
      pdo.valid = (cob_id & canopen::kPdoCobIdInvalid) == 0;
      pdo.cob_id = cob_id & 0x7FFu;
      pdo.transmission_type = static_cast<std::uint8_t>(dictionary_.get({comm_index, 2}));
      const std::uint32_t count = dictionary_.get({map_index, 0});
      for (std::uint32_t k = 1; k <= count && k <= kMaxMappedObjects; ++k) {
        const std::uint32_t mapping = dictionary_.get({map_index, static_cast<std::uint8_t>(k)});
        ObjectEntry* entry = dictionary_.find(canopen::mapped_object(mapping));
        if (entry == nullptr) break;  // Checked when written; a default never lacks its object.
        const auto bytes = static_cast<std::size_t>(canopen::mapped_bits(mapping)) / 8;
        if (pdo.bytes + bytes > 8) break;
        pdo.entries[pdo.count++] = {entry, bytes};
        pdo.bytes += bytes;
      }
    }
  };
  build(rpdos_, canopen::kRpdoCommunication, canopen::kRpdoMapping);
  build(tpdos_, canopen::kTpdoCommunication, canopen::kTpdoMapping);
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
    if (mode != 8 && mode != 9) return code(SdoAbortCode::kInvalidValue);
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
  previous_controlword_ = controlword;
  const DriveState next = cia402::drive_state_after(drive_state_, command);
  if (next == drive_state_) return;
  if (drive_state_ == DriveState::kFault) {
    // Transition 15: the fault is cleared and the drive says so (EMCY 0x0000).
    following_error_ = false;
    error_code_->value = 0;
    error_register_->value = 0;
    send_emergency(kEmcyErrorReset);
  }
  enter(next);
}

void EmulatedDrive::enter(DriveState state) noexcept {
  drive_state_ = state;
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
  if (!hal::is_enabled(drive_state_) || !targets_written_) return;
  const double torque_nm =
      static_cast<double>(torque_offset_->as_integer()) / 1000.0 * config_.rated_torque_nm;
  if (mode_->value == 8) {
    const std::int64_t target = std::clamp(
        target_position_->as_integer(), min_position_->as_integer(), max_position_->as_integer());
    demand_rad_ = units_.to_rad(static_cast<std::int32_t>(target));
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
    // Transition 14: the fault reaction ends when the joint stands still.
    if (drive_state_ == DriveState::kFaultReactionActive && servo_.at_rest()) {
      enter(DriveState::kFault);
    }
  }
  if (stepped) update_actual_values();
}

void EmulatedDrive::update_actual_values() noexcept {
  const std::int32_t actual_counts = units_.to_counts(servo_.encoder_position_rad());
  position_actual_->value = static_cast<std::uint32_t>(actual_counts);
  velocity_actual_->value =
      static_cast<std::uint32_t>(units_.to_counts(servo_.encoder_velocity_rad_s()));
  const bool enabled = hal::is_enabled(drive_state_);
  const double torque_per_mille = enabled ? static_cast<double>(torque_offset_->as_integer()) : 0.0;
  torque_actual_->value =
      static_cast<std::uint32_t>(static_cast<std::int16_t>(torque_per_mille)) & 0xFFFFu;
  const std::int32_t demand_counts = units_.to_counts(demand_rad_);
  position_demand_->value = static_cast<std::uint32_t>(demand_counts);
  mode_display_->value = mode_->value;

  std::uint32_t status = cia402::statusword_of(drive_state_) | cia402::kStatusRemote;
  if (enabled) {
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
