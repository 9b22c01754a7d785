#pragma once

#include "cambio/canopen/can_rig.hpp"
#include "cambio/config/rig_config.hpp"

namespace cambio::canopen {

/// The rig's CANopen side: every bus of can_buses, one CanGroupInfo per group (its can_bus and
/// can settings, defaults where the file gives none), a drive for every joint with a can section
/// (its command mode from the joint's servo.command).
CanRigInfo can_rig_from_config(const config::RigConfig& rig);

}  // namespace cambio::canopen
