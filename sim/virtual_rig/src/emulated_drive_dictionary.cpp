// The emulated drive's CiA 301/402 object dictionary (what firmware_config/eds/ describes).
#include "cambio/canopen/pdo_layout.hpp"
#include "cambio/virtual_rig/emulated_drive.hpp"
#include "emulated_drive_detail.hpp"

namespace cambio::virtual_rig {

using namespace emulated_drive_detail;

void EmulatedDrive::build_dictionary() {
  add_communication_objects();
  add_pdo_objects();
  add_cia402_objects();
  dictionary_.finalise();
  find_live_objects();
}

// CiA 301 communication objects: identity, error register, SYNC, heartbeat.
void EmulatedDrive::add_communication_objects() {
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
}

// PDO communication and mapping: by default the minimum set the stack's layout names (RPDO1 and
// TPDO1 valid).
void EmulatedDrive::add_pdo_objects() {
  auto& d = dictionary_;
  const int id = config_.node_id;
  using enum DataType;
  using enum Access;
  const canopen::PdoLayout layout = canopen::pdo_layout(config_.mode, canopen::CanGroupSettings{});
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
    // PDOs the stack's layout does not name (3 and 4) start invalid and empty.
    const canopen::PdoMapping unused{};
    const auto k = static_cast<std::size_t>(n);
    add_mapping(static_cast<std::uint16_t>(canopen::kRpdoMapping + i),
                k < layout.rpdos.size() ? layout.rpdos[k] : unused);
    add_mapping(static_cast<std::uint16_t>(canopen::kTpdoMapping + i),
                k < layout.tpdos.size() ? layout.tpdos[k] : unused);
  }
}

// CiA 402 objects: the drive's state machine, targets, actual values, limits.
void EmulatedDrive::add_cia402_objects() {
  auto& d = dictionary_;
  using enum DataType;
  using enum Access;
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
  // Read-only, not const: the emulation takes it from the rig joint's max_effort_nm (1 N m, the
  // EDS's DefaultValue, without one), so it differs from drive to drive.
  d.add(cia402::kRatedTorque, "Rated torque", kUnsigned32, kReadOnly,
        saturating_counts(config_.rated_torque_nm * 1000.0));
  d.add(cia402::kTorqueActualValue, "Torque actual value", kInteger16, kReadOnly, 0, true);
  d.add(cia402::kTargetPosition, "Target position", kInteger32, kReadWrite, 0, true);
  d.add(cia402::kHomeOffset, "Home offset", kInteger32, kReadWrite, 0);
  d.add({cia402::kMinSoftwarePositionLimit.index, 0}, "Highest sub-index supported", kUnsigned8,
        kConst, 2);
  d.add(cia402::kMinSoftwarePositionLimit, "Min position limit", kInteger32, kReadWrite,
        counts(config_.servo.min_position_rad));
  d.add(cia402::kMaxSoftwarePositionLimit, "Max position limit", kInteger32, kReadWrite,
        counts(config_.servo.max_position_rad));
  d.add(cia402::kMaxProfileVelocity, "Max profile velocity", kUnsigned32, kReadWrite,
        saturating_counts(config_.servo.max_velocity_rad_s * units_.counts_per_rad));
  d.add(cia402::kHomingMethod, "Homing method", kInteger8, kReadWrite, 0);
  d.add({cia402::kHomingSwitchSpeed.index, 0}, "Highest sub-index supported", kUnsigned8, kConst,
        2);
  d.add(cia402::kHomingSwitchSpeed, "Speed during search for switch", kUnsigned32, kReadWrite, 0);
  d.add(cia402::kHomingZeroSpeed, "Speed during search for zero", kUnsigned32, kReadWrite, 0);
  d.add(cia402::kHomingAcceleration, "Homing acceleration", kUnsigned32, kReadWrite, 0);
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
}

// The objects the drive reads and writes every cycle, found once.
void EmulatedDrive::find_live_objects() {
  auto& d = dictionary_;
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
  home_offset_ = d.find(cia402::kHomeOffset);
  homing_method_ = d.find(cia402::kHomingMethod);
  homing_switch_speed_ = d.find(cia402::kHomingSwitchSpeed);
  homing_zero_speed_ = d.find(cia402::kHomingZeroSpeed);
}

}  // namespace cambio::virtual_rig
