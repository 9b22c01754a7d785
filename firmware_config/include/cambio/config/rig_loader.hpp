#pragma once

#include <string>
#include <vector>

#include "cambio/config/map_reader.hpp"
#include "cambio/config/rig_config.hpp"

namespace cambio::config {

/// Loads and validates a rig file (rigs/*.yaml), overrides applied first. Throws ConfigError
/// with every problem found: unknown or missing keys, wrong types, out-of-range values and
/// inconsistent settings (a lower limit above the upper one, a rate of 0, a group naming an
/// unknown joint, a joint in two groups, a stereo baseline that disagrees with the eyes' joint
/// origins, a socketcan group without a bus, duplicate CAN node ids on one bus, ...).
RigConfig load_rig(const std::string& path, const std::vector<ConfigOverride>& overrides = {});
/// The same from YAML text (tests); `name` stands for the file in messages.
RigConfig load_rig_from_string(const std::string& yaml, const std::string& name,
                               const std::vector<ConfigOverride>& overrides = {});
/// Reads a rig from an already loaded document (for callers that embed a rig).
RigConfig read_rig(MapReader root, const std::string& file);

/// Default loops when the rig file does not define them: joint 1000 Hz, control 200 Hz,
/// perception 60 Hz, camera 30 Hz.
std::vector<LoopConfig> default_loops();

/// Bits one classic CAN frame with an 11-bit identifier and `data_bytes` data bytes takes on the
/// wire in the worst case: 47 bits of framing and interframe space, the data, and the most stuff
/// bits the 34 + 8 * data_bytes stuffed bits can need (8 data bytes: 135 bits; SYNC, 0 bytes: 55).
int can_frame_worst_case_bits(int data_bytes);

/// Worst-case share of `bus`'s bitrate the joint loop's CANopen traffic takes (1.0 = saturated):
/// per SYNC, each joint of a socketcan group on the bus receives one RPDO and sends one TPDO of
/// 8 data bytes, plus the SYNC frame, at the joint loop's rate. An upper bound for CAN FD buses
/// too (FD frames at the faster data bitrate take less time). Loading refuses a load above
/// kMaxCanBusLoad.
double joint_loop_can_load(const RigConfig& rig, const CanBusConfig& bus);
inline constexpr double kMaxCanBusLoad = 0.9;

}  // namespace cambio::config
