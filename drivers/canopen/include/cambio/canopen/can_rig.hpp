#pragma once

// What the CANopen side knows of a rig besides the HAL's HardwareInfo: the buses, each group's
// bus and CANopen settings, each joint's CiA 402 drive. The application builds it from the rig
// file's can_buses, groups.<g>.can_bus / .can and joints.<j>.can sections (can_rig_from_config.hpp)
// and hands it to the socketcan backend's maker and checker; the HAL's types carry none of it.

#include <cstdint>
#include <map>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "cambio/hal/joint_group.hpp"

namespace cambio::canopen {

struct CanBusInfo {
  std::string name;       ///< The rig's name for it (groups refer to it).
  std::string interface;  ///< Kernel interface, e.g. "can0", "vcan0".
  std::int64_t bitrate_bit_s = 1'000'000;
  bool fd = false;
  std::int64_t data_bitrate_bit_s = 0;
};

/// What the master needs per joint group besides its joints' drives (groups.<g>.can).
struct CanGroupSettings {
  /// Heartbeat every drive produces (0x1017); the master declares a drive lost after 3 missed
  /// periods (latched kJointCommLost).
  double heartbeat_period_s = 0.1;
  /// A joint's reading is flagged kJointStale after this many SYNCs with no TPDO answer.
  int stale_after_missed_syncs = 3;
  double sdo_timeout_s = 0.1;  ///< One SDO request's answer timeout at configure time.
  /// Optional PDO objects. The minimum set is controlword + target out and statusword + position
  /// back; these add velocity/torque offsets (0x60B1/0x60B2) out and velocity/torque actual
  /// (0x606C/0x6077) back, and the bus-load model counts them.
  bool velocity_feedforward = false;
  bool effort_feedforward = false;
  bool velocity_feedback = false;
  bool effort_feedback = false;
};

/// How a drive finds its reference (CiA 402 homing mode 6), for joints without absolute encoders.
/// Written to 0x6098, 0x6099:1/2, 0x609A and 0x607C in the drive's counts; homing runs at
/// activate, before the joint is ever commanded in CSP or CSV.
struct HomingSettings {
  int method = 0;  ///< CiA 402 homing method (0x6098), e.g. 17/18 limit switch, 33/34 index.
  double switch_speed_rad_s = 0.0;   ///< 0x6099:1, the search for the switch.
  double zero_speed_rad_s = 0.0;     ///< 0x6099:2, the search for the edge or index pulse.
  double acceleration_rad_s2 = 0.0;  ///< 0x609A.
  /// CiA 402's home offset (0x607C): the zero position is the home position plus this, so at
  /// the home position the joint reads -offset_rad.
  double offset_rad = 0.0;
  double timeout_s = 0.0;  ///< The master gives up (homing timeout) after this long.
};

/// The CiA 402 drive behind a joint: what the master needs to address it, convert units and
/// write its parameters (position limits and max velocity come from the joint's limits).
struct JointDriveInfo {
  int node_id = 0;                          ///< CANopen node id, 1..127.
  double gear_ratio = 1.0;                  ///< Motor turns per joint turn.
  std::int64_t encoder_counts_per_rev = 0;  ///< Motor encoder counts per motor turn.
  /// CiA 402 following error window (0x6065): the drive faults (EMCY 0x8611) when its position
  /// lags its demand by more than this. 0 = leave the drive's own setting.
  double following_error_window_rad = 0.0;
  /// Cyclic synchronous position (default) or cyclic synchronous velocity.
  hal::CommandMode mode = hal::CommandMode::kPosition;
  /// None: the encoder is absolute, the drive is driven from where it says the joint is.
  std::optional<HomingSettings> homing;
};

/// One joint group's CANopen side.
struct CanGroupInfo {
  std::string name;  ///< The HardwareInfo group it belongs to.
  std::string bus;   ///< The bus it is driven on ("" when it names none).
  CanGroupSettings settings;
};

struct CanRigInfo {
  std::vector<CanBusInfo> buses;
  std::vector<CanGroupInfo> groups;                           ///< One per rig group.
  std::map<std::string, JointDriveInfo, std::less<>> drives;  ///< By joint name.

  const CanBusInfo* find_bus(std::string_view bus_name) const {
    for (const auto& bus : buses) {
      if (bus.name == bus_name) return &bus;
    }
    return nullptr;
  }
  const CanGroupInfo* find_group(std::string_view group_name) const {
    for (const auto& group : groups) {
      if (group.name == group_name) return &group;
    }
    return nullptr;
  }
  const JointDriveInfo* find_drive(std::string_view joint_name) const {
    const auto it = drives.find(joint_name);
    return it != drives.end() ? &it->second : nullptr;
  }
};

}  // namespace cambio::canopen
