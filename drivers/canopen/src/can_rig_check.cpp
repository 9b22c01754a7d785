#include "cambio/canopen/can_rig_check.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <map>
#include <stdexcept>
#include <string>

#include "cambio/canopen/can_bus_load.hpp"
#include "cambio/canopen/drive_parameters.hpp"

namespace cambio::canopen {

namespace {

/// Up to 9 significant digits, no trailing zeros, as the rig loader's messages write numbers.
std::string number(double value) {
  char buffer[32];
  std::snprintf(buffer, sizeof buffer, "%.9g", value);
  return buffer;
}

std::string in_quotes(std::string_view text) {
  return "\"" + std::string(text) + "\"";
}

std::string bus_names(const CanRigInfo& can_rig) {
  std::string names;
  for (const auto& bus : can_rig.buses) names += (names.empty() ? "" : ", ") + bus.name;
  return names.empty() ? "none defined" : names;
}

/// The bus exists and its node ids are unique; for the master's groups, a bus of their own and a
/// drive per joint in one command mode.
void check_group(const hal::HardwareInfo& hardware, const hal::JointGroupInfo& group,
                 const CanRigInfo& can_rig, std::string_view backend,
                 std::map<std::string, std::map<int, std::string>>& nodes,
                 std::map<std::string, std::string>& master_of_bus,
                 std::vector<hal::SettingProblem>& problems) {
  const bool mastered = group.backend == backend;
  const CanGroupInfo* can_group = can_rig.find_group(group.name);
  const std::string bus_key = "groups." + group.name + ".can_bus";
  if (can_group == nullptr || can_group->bus.empty()) {
    if (mastered) {
      problems.push_back({bus_key, "missing key (a " + std::string(backend) +
                                       " group needs can_bus naming one of can_buses: " +
                                       bus_names(can_rig) + ")"});
    }
    return;
  }
  if (can_rig.find_bus(can_group->bus) == nullptr) {
    problems.push_back({bus_key, "expected one of can_buses (" + bus_names(can_rig) + "), found " +
                                     in_quotes(can_group->bus)});
    return;
  }
  if (mastered) {
    const auto [master, first] = master_of_bus.emplace(can_group->bus, group.name);
    if (!first) {
      problems.push_back({bus_key, "expected a bus no other " + std::string(backend) +
                                       " group drives (each group produces its bus's SYNC at its "
                                       "own rate), found " +
                                       in_quotes(can_group->bus) + ", already driven by group " +
                                       master->second});
    }
  }
  const JointDriveInfo* first_drive = nullptr;
  for (const auto& joint_name : group.joints) {
    const JointDriveInfo* drive = can_rig.find_drive(joint_name);
    if (drive == nullptr) {
      if (mastered) {
        problems.push_back({"joints." + joint_name + ".can",
                            "missing key (a joint of " + std::string(backend) + " group " +
                                group.name +
                                " needs can: {node_id, gear_ratio, encoder_counts_per_rev})"});
      }
      continue;
    }
    if (mastered && first_drive != nullptr && drive->mode != first_drive->mode) {
      problems.push_back({"joints." + joint_name + ".servo.command",
                          "expected the command mode of the other joints of group " + group.name +
                              " (one PDO layout per group), found a different one"});
    }
    if (first_drive == nullptr) first_drive = drive;
    if (const hal::JointInfo* joint = hardware.find_joint(joint_name); mastered && joint) {
      try {
        // The master's own check, so the rig is refused here and not after the run has begun.
        check_drive_units(*joint, *drive);
      } catch (const std::invalid_argument& error) {
        problems.push_back({"joints." + joint_name + ".can.gear_ratio",
                            std::string("expected units a drive can hold: ") + error.what()});
      }
    }
    const auto [owner, inserted] = nodes[can_group->bus].emplace(drive->node_id, joint_name);
    if (!inserted) {
      problems.push_back({"joints." + joint_name + ".can.node_id",
                          "expected a node id unique on bus " + can_group->bus + ", found " +
                              std::to_string(drive->node_id) + " (already used by " +
                              owner->second + ")"});
    }
  }
}

/// The joint loops' worst-case traffic fits the bus; else the advice names the group that takes
/// the most of it: the rate it may run at with the others unchanged, or a bus of its own.
void check_load(const hal::HardwareInfo& hardware, const CanRigInfo& can_rig, const CanBusInfo& bus,
                std::string_view backend, std::vector<hal::SettingProblem>& problems) {
  const CanBusLoad load = can_bus_load(hardware, can_rig, bus, backend);
  if (load.load <= kMaxCanBusLoad || load.groups.empty()) return;
  const auto largest = std::max_element(
      load.groups.begin(), load.groups.end(),
      [](const CanGroupLoad& x, const CanGroupLoad& y) { return x.bit_s < y.bit_s; });
  std::string traffic;
  for (const auto& group : load.groups) {
    traffic += (traffic.empty() ? "" : ", ") + group.group + " " + std::to_string(group.drives) +
               (group.drives == 1 ? " drive at " : " drives at ") + number(group.rate_hz) + " Hz";
  }
  const double budget_bit_s = kMaxCanBusLoad * static_cast<double>(bus.bitrate_bit_s);
  const double max_rate_hz =
      (budget_bit_s - (load.bit_s - largest->bit_s) - largest->heartbeat_bit_s) /
      largest->bits_per_cycle;
  const double needed_bitrate_bit_s = std::ceil(load.bit_s / kMaxCanBusLoad);
  // A group's rate below 0.1 Hz is no joint loop (the rig loader's lowest rate).
  std::string advice = max_rate_hz >= 0.1
                           ? "set groups." + largest->group + ".rate_hz to at most " +
                                 number(std::floor(max_rate_hz)) + " Hz"
                           : "give group " + largest->group + " a bus of its own";
  if (!bus.fd && needed_bitrate_bit_s <= 1'000'000) {
    advice += ", raise bitrate_bit_s to at least " + number(needed_bitrate_bit_s);
  }
  advice += " or split the groups over more buses";
  problems.push_back({"can_buses." + bus.name + ".bitrate_bit_s",
                      "expected a bitrate that carries the joint loops' CANopen traffic within " +
                          number(kMaxCanBusLoad * 100) + "% (" + traffic + ": " +
                          number(std::round(load.bit_s)) + " bit/s worst case), found " +
                          std::to_string(bus.bitrate_bit_s) + " bit/s (" +
                          number(std::round(load.load * 1000) / 10) + "% load); " + advice});
}

}  // namespace

std::vector<hal::SettingProblem> check_can_rig(const hal::HardwareInfo& hardware,
                                               const CanRigInfo& can_rig,
                                               std::string_view backend) {
  std::vector<hal::SettingProblem> problems;
  std::map<std::string, std::map<int, std::string>> nodes;  // bus -> node id -> joint
  std::map<std::string, std::string> master_of_bus;         // bus -> the group producing SYNC
  for (const auto& group : hardware.groups) {
    check_group(hardware, group, can_rig, backend, nodes, master_of_bus, problems);
  }
  for (const auto& bus : can_rig.buses) check_load(hardware, can_rig, bus, backend, problems);
  return problems;
}

}  // namespace cambio::canopen
