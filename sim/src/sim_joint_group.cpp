#include "sim_joint_group.hpp"

namespace cambio::sim {

SimJointGroup::SimJointGroup(hal::JointGroupInfo info, GroupLink& link)
    : info_(std::move(info)), link_(link) {
  (void)link_.readings.read(last_);
}

hal::Status SimJointGroup::read(std::span<hal::JointState> out, std::int64_t& stamp_ns) {
  if (out.size() != info_.joints.size()) return hal::Status::kRejected;
  // A read that keeps meeting the physics loop mid-write gives up (bounded): the last good
  // readings stand, their stamps telling how old they are.
  (void)link_.readings.read(last_);
  hal::Status status = hal::Status::kOk;
  for (std::size_t k = 0; k < out.size(); ++k) {
    out[k] = last_.states[k];
    out[k].status_bits |= clamped_[k].load(std::memory_order_relaxed);
    if ((out[k].status_bits & hal::kJointLatchingBits) != 0) status = hal::Status::kFault;
  }
  stamp_ns = last_.stamp_ns;
  return status;
}

hal::Status SimJointGroup::write(std::span<const hal::JointCommand> commands) {
  if (commands.size() != info_.joints.size()) return hal::Status::kRejected;
  GroupCommands block;
  block.count = static_cast<std::uint32_t>(commands.size());
  for (std::size_t k = 0; k < commands.size(); ++k) {
    hal::JointCommand command = commands[k];
    const bool clamped = hal::clamp_command(command, info_.limits[k]);
    block.commands[k] = command;
    clamped_[k].store(clamped ? hal::kJointCommandClamped : 0u, std::memory_order_relaxed);
  }
  link_.commands.write(block);
  return hal::Status::kOk;
}

hal::Status SimJointGroup::request(hal::DriveRequest request, int joint) {
  const int count = static_cast<int>(info_.joints.size());
  if (joint != kAllJoints && (joint < 0 || joint >= count)) return hal::Status::kRejected;
  // The sim's joints read absolute positions: none homes.
  if (request == hal::DriveRequest::kHome) {
    return joint == kAllJoints ? hal::Status::kOk : hal::Status::kRejected;
  }
  const int first = joint == kAllJoints ? 0 : joint;
  const int last = joint == kAllJoints ? count : joint + 1;
  for (int k = first; k < last; ++k) {
    auto& word = link_.requests[static_cast<std::size_t>(k)];
    // Bump the count so the physics loop tells this request from the last one, even if equal.
    std::uint32_t old = word.load(std::memory_order_relaxed);
    while (!word.compare_exchange_weak(
        old, (((old >> 8) + 1) << 8) | static_cast<std::uint32_t>(request),
        std::memory_order_release, std::memory_order_relaxed)) {
    }
  }
  return hal::Status::kOk;
}

}  // namespace cambio::sim
