#pragma once

// The socketcan backend's check of a rig's CANopen side, run by `check-config` and `cambio run`
// before anything starts (hal::BackendFactory::check): what the master needs and cannot work
// without, found on the whole rig at once, each problem at its rig key.

#include <string_view>
#include <vector>

#include "cambio/canopen/can_rig.hpp"
#include "cambio/hal/backend_factory.hpp"

namespace cambio::canopen {

/// For every group that names a bus, whichever backend drives it (the virtual rig emulates
/// those): the bus is one of can_buses and each node id is used once on it. For the groups on
/// `backend` (the master): each names a bus, no other such group shares it (each produces its
/// bus's SYNC), each joint has a drive, the drives of a group run one command mode, and every
/// bus carries the joint loops' worst-case traffic within kMaxCanBusLoad (else the advice names
/// the rate the busiest group may run at, or a bitrate that would do).
std::vector<hal::SettingProblem> check_can_rig(const hal::HardwareInfo& hardware,
                                               const CanRigInfo& can_rig, std::string_view backend);

}  // namespace cambio::canopen
