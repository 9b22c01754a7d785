#include "sim_joint_group.hpp"

#include <algorithm>
#include <cmath>

namespace cambio::sim {

SimJointGroup::SimJointGroup(hal::JointGroupInfo info, GroupLink& link)
    : info_(std::move(info)), link_(link) {}

hal::Status SimJointGroup::read(std::span<hal::JointState> out, std::int64_t& stamp_ns) {
  if (out.size() != info_.joints.size()) return hal::Status::kRejected;
  GroupReadings readings;
  link_.readings.read(readings);
  for (std::size_t k = 0; k < out.size(); ++k) {
    out[k] = readings.states[k];
    out[k].status_bits |= clamped_[k].load(std::memory_order_relaxed);
  }
  stamp_ns = readings.stamp_ns;
  return hal::Status::kOk;
}

hal::Status SimJointGroup::write(std::span<const hal::JointCommand> commands) {
  if (commands.size() != info_.joints.size()) return hal::Status::kRejected;
  GroupCommands block;
  block.count = static_cast<std::uint32_t>(commands.size());
  for (std::size_t k = 0; k < commands.size(); ++k) {
    const auto& limits = info_.limits[k];
    hal::JointCommand command = commands[k];
    const bool clamped = hal::clamp_command(command, limits);
    block.commands[k] = command;
    clamped_[k].store(clamped ? hal::kJointCommandClamped : 0u, std::memory_order_relaxed);
  }
  link_.commands.write(block);
  return hal::Status::kOk;
}

}  // namespace cambio::sim
