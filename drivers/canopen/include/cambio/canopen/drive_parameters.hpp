#pragma once

// The CiA 402 parameters a master writes to each drive from the rig (hal::HardwareInfo and
// its CANopen side, can_rig.hpp) at
// configure time, then reads back (object_write.hpp): a drive that did not take a value is not
// enabled.
//   0x6060     modes of operation: 8 (CSP) or 9 (CSV), from JointDriveInfo::mode
//   0x607D:1/2 software position limits, counts (swapped when the gear ratio is negative)
//   0x607F     max profile velocity, counts/s, from the joint's max velocity
//   0x6065     following error window, counts (only when the rig sets it)
//   0x1017     producer heartbeat time, ms, from the group's heartbeat period
//   0x60C2:1/2 interpolation time period: value * 10^index s = the group's SYNC period
// and, for a joint that homes, the homing parameters (homing_parameter_writes).

#include <cstdint>
#include <vector>

#include "cambio/canopen/can_rig.hpp"
#include "cambio/canopen/object_write.hpp"
#include "cambio/hal/hardware_info.hpp"

namespace cambio::canopen {

/// CiA 402's interpolation time period (0x60C2): value (UNSIGNED8) * 10^index (INTEGER8) s.
struct InterpolationPeriod {
  std::uint8_t value = 1;
  std::int8_t index = -3;
};

/// The exact representation of `period_s` with the largest unit (index from 0 down to -6) whose
/// value fits 1..255; else the closest. Throws std::invalid_argument for a period outside
/// 1 us .. 255 s.
InterpolationPeriod interpolation_period(double period_s);

/// The fewest encoder counts per joint turn the master accepts: one count is at most a degree
/// (below it, every command of a fine servo rounds to the same count).
inline constexpr double kMinCountsPerJointTurn = 360.0;

/// Throws std::invalid_argument naming the joint when `drive`'s units cannot represent `joint`:
/// no encoder counts or gear ratio, a resolution coarser than kMinCountsPerJointTurn, or a
/// position limit, the maximum velocity or the following error window beyond a drive's
/// INTEGER32 counts. The rig's check runs it before anything is built; drive_parameter_writes()
/// again before it writes.
void check_drive_units(const hal::JointInfo& joint, const JointDriveInfo& drive);

/// The writes for `joint`'s `drive` in `group` (its CANopen settings `settings`), whose SYNC runs
/// at `rate_hz`. Throws std::invalid_argument naming the joint for values a drive cannot hold (a
/// limit beyond INTEGER32 counts, a heartbeat period beyond 65535 ms).
std::vector<ObjectWrite> drive_parameter_writes(const hal::JointInfo& joint,
                                                const JointDriveInfo& drive,
                                                const hal::JointGroupInfo& group,
                                                const CanGroupSettings& settings, double rate_hz);

/// The homing parameters of a joint that homes (none for `drive.homing` unset), in the drive's
/// units: 0x6098 method, 0x6099:1/2 switch and zero speeds (counts/s), 0x609A acceleration
/// (counts/s2), 0x607C home offset (counts, signed as the gear turns). Throws
/// std::invalid_argument naming the joint for a value beyond the objects' types.
std::vector<ObjectWrite> homing_parameter_writes(const hal::JointInfo& joint,
                                                 const JointDriveInfo& drive);

}  // namespace cambio::canopen
