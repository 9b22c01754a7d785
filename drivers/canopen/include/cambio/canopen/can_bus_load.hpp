#pragma once

// The worst-case CANopen traffic the joint loops put on a bus: every cycle each drive's mapped
// PDOs (exactly what pdo_layout() maps) and the group's SYNC, plus the drives' heartbeats. The
// socketcan backend's check refuses a rig that plans more than kMaxCanBusLoad of a bus, and
// `check-config` prints it.

#include <string>
#include <string_view>
#include <vector>

#include "cambio/canopen/can_rig.hpp"
#include "cambio/hal/hardware_info.hpp"

namespace cambio::canopen {

/// Bits one classic CAN frame with an 11-bit identifier and `data_bytes` data bytes takes on the
/// wire in the worst case: 47 bits of framing and interframe space, the data, and the most stuff
/// bits the 34 + 8 * data_bytes stuffed bits can need (8 data bytes: 135 bits; SYNC, 0 bytes: 55).
int can_frame_worst_case_bits(int data_bytes);

/// One CAN-driven group's share of its bus, worst case.
struct CanGroupLoad {
  std::string group;
  double rate_hz = 0.0;  ///< The group's joint-loop (SYNC) rate.
  int drives = 0;
  /// Per cycle: every drive's mapped PDOs (RPDO1, RPDO2 if feed-forward is mapped, TPDO1, TPDO2
  /// if feedback is), then one SYNC.
  int bits_per_cycle = 0;
  double heartbeat_bit_s = 0.0;  ///< One 1-byte heartbeat frame per drive per period.
  double bit_s = 0.0;            ///< bits_per_cycle * rate_hz + heartbeat_bit_s.
};

/// The joint loops' CANopen traffic on one bus.
struct CanBusLoad {
  std::vector<CanGroupLoad> groups;  ///< The CAN-driven groups on the bus, rig order.
  double bit_s = 0.0;
  double load = 0.0;  ///< bit_s / the bus's bitrate (1.0 = saturated).
};

/// Worst-case traffic on `bus` of the groups `hardware` puts on backend `backend` (the master
/// that drives them), each at its own rate (JointGroupInfo::rate_hz), counting exactly the PDOs
/// pdo_layout() maps for its drives' command mode and its feed-forward and feedback settings. An
/// upper bound for CAN FD buses too (FD frames at the faster data bitrate take less time).
CanBusLoad can_bus_load(const hal::HardwareInfo& hardware, const CanRigInfo& can_rig,
                        const CanBusInfo& bus, std::string_view backend);

/// The highest worst-case load a rig may plan for a bus: the rest is headroom for what the model
/// does not count (SDO, NMT and EMCY traffic, frames retransmitted after an error) and keeps the
/// lowest-priority PDO's latency within a SYNC period (the usual CANopen design rule).
inline constexpr double kMaxCanBusLoad = 0.6;

}  // namespace cambio::canopen
