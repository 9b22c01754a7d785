#pragma once

// `cambio virtual-rig`'s run: one emulated CiA 402 drive per CAN joint of the rig on the kernel
// CAN interfaces its can_buses name, until a stop signal or the end time, then each drive's
// counts.

#include <cstdint>

#include "cambio/config/rig_config.hpp"
#include "cambio/virtual_rig/virtual_rig.hpp"

namespace cambio::app {

/// Emulates the drives of `rig` (its CANopen side checked by the caller) with `options` until
/// SIGINT/SIGTERM or `duration_s` (0: no end), printing the buses, drives and faults first and
/// every drive's counters and the peak RSS last. Returns the exit status: kExitBadInput (the reason
/// printed) when the drives cannot be made or an interface cannot be opened, the signal's status
/// when one stopped the run.
int run_virtual_rig(const config::RigConfig& rig, const virtual_rig::VirtualRigOptions& options,
                    double duration_s);

}  // namespace cambio::app
