#pragma once

// What the master asks of each drive of a CAN joint group, taken from the master's own functions
// so that the EDS check follows the master when it changes: the SDO writes of
// drive_parameter_writes() and pdo_configuration_writes(), the read-backs, statusword and position
// reads of reconfiguration_plan() (the same steps configure() takes), the reads configure() makes
// besides (socketcan_backend.cpp: device type, rated torque when effort is mapped), and the PDO
// layout of pdo_layout().

#include <string>
#include <string_view>
#include <vector>

#include "cambio/canopen/can_rig.hpp"
#include "cambio/canopen/object_write.hpp"
#include "cambio/canopen/pdo_layout.hpp"
#include "cambio/hal/hardware_info.hpp"

namespace cambio::canopen::eds {

/// The master's view of one CAN joint group, as socketcan_backend.cpp configures it.
struct CanGroupView {
  hal::JointGroupInfo group;           ///< Joints in order, limits; rate_hz > 0 (SYNC rate).
  std::vector<hal::JointInfo> joints;  ///< One per group joint, same order.
  std::vector<JointDriveInfo> drives;  ///< One per group joint, same order.
  CanGroupSettings settings;
};

/// The view of `group_name`; a group rate of 0 takes `default_rate_hz` (the joint loop's, as the
/// backend does). Throws std::invalid_argument naming an unknown group, a group without a CAN bus
/// or a joint without a drive (joints.<j>.can).
CanGroupView can_group_view(const hal::HardwareInfo& hardware, const CanRigInfo& can_rig,
                            std::string_view group_name, double default_rate_hz);

/// One SDO access the master makes to a drive at configure time (and again after a reboot).
struct ObjectUse {
  enum class Kind : std::uint8_t { kWrite, kRead };
  Kind kind = Kind::kWrite;
  ObjectWrite access;  ///< The object, and for a write the value and size.
};

/// Every SDO access to `joint`'s drive, in the master's order (duplicates kept). Throws
/// std::invalid_argument when the rig's values do not fit the master's objects at all.
std::vector<ObjectUse> master_object_uses(const CanGroupView& view, std::size_t joint);

/// The PDO layout the master maps on every drive of the group.
PdoLayout master_pdo_layout(const CanGroupView& view);

/// What the master does with `object` (e.g. "producer heartbeat time: the master declares a drive
/// lost after 3 missed periods") and the rig setting that decides it, for `joint` of `view`
/// (e.g. "groups.head.can.heartbeat_period_ms"); empty when no rig setting avoids the object.
struct ObjectPurpose {
  std::string what;
  std::string rig_setting;
  bool optional = false;  ///< Turning `rig_setting` off makes the master leave the object alone.
};
ObjectPurpose object_purpose(ObjectAddress object, const CanGroupView& view, std::size_t joint);

}  // namespace cambio::canopen::eds
