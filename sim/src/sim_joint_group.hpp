#pragma once

#include <array>
#include <atomic>

#include "cambio/hal/joint_group.hpp"
#include "cambio/sim/physics_loop.hpp"

namespace cambio::sim {

/// A rig joint group served by the sim: write() hands targets to the physics loop's servo
/// models, request() records a lifecycle request per joint for the physics loop to walk, read()
/// returns the encoders' view with each drive's state. All real-time safe and lock-free; called
/// from the joint loop's thread.
class SimJointGroup final : public hal::JointGroup {
 public:
  SimJointGroup(hal::JointGroupInfo info, GroupLink& link);

  const hal::JointGroupInfo& info() const override { return info_; }
  hal::Status read(std::span<hal::JointState> out, std::int64_t& stamp_ns) override;
  hal::Status write(std::span<const hal::JointCommand> commands) override;
  hal::Status request(hal::DriveRequest request, int joint = kAllJoints) override;

 private:
  hal::JointGroupInfo info_;
  GroupLink& link_;
  std::array<std::atomic<std::uint32_t>, kMaxJointsPerGroup> clamped_{};
  GroupReadings last_;  ///< The last consistent readings (kept when a read comes back torn).
};

}  // namespace cambio::sim
