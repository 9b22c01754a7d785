#include "cambio/control/believed_joints.hpp"

#include <algorithm>
#include <stdexcept>
#include <string>

namespace cambio::control {

BelievedJoints::BelievedJoints(std::vector<Source> sources, int rig_joint_count)
    : sources_(std::move(sources)),
      frames_(sources_.size()),
      reported_(static_cast<std::size_t>(std::max(rig_joint_count, 0)), 0),
      driven_(reported_.size(), 0),
      enabled_(reported_.size(), 0),
      rig_joint_count_(rig_joint_count) {
  for (std::size_t s = 0; s < sources_.size(); ++s) {
    if (sources_[s].states == nullptr) {
      throw std::invalid_argument("believed joints: source " + std::to_string(s) +
                                  " has no state channel");
    }
    for (const int index : sources_[s].rig_indices) {
      if (index < 0 || index >= rig_joint_count) {
        throw std::invalid_argument("believed joints: rig index " + std::to_string(index) +
                                    " outside the rig's " + std::to_string(rig_joint_count) +
                                    " joints");
      }
    }
    if (static_cast<int>(sources_[s].rig_indices.size()) > kMaxJoints) {
      throw std::invalid_argument("believed joints: a source lists more than kMaxJoints joints");
    }
  }
}

bool BelievedJoints::read(std::span<double> q_rig_rad) noexcept {
  if (static_cast<int>(q_rig_rad.size()) != rig_joint_count_) return false;
  holding_ = false;
  for (std::size_t s = 0; s < sources_.size(); ++s) {
    JointStateFrame& frame = frames_[s];
    (void)sources_[s].states->read(frame);  // A torn read keeps the last clean frame.
    holding_ |= frame.holding;
    const auto& indices = sources_[s].rig_indices;
    const int count = std::min(frame.count, static_cast<int>(indices.size()));
    for (int i = 0; i < count; ++i) {
      const auto rig = static_cast<std::size_t>(indices[static_cast<std::size_t>(i)]);
      const hal::JointState& state = frame.states[static_cast<std::size_t>(i)];
      q_rig_rad[rig] = state.position_rad;
      reported_[rig] = 1;
      enabled_[rig] =
          (state.status_bits & (hal::kJointNotEnabled | hal::kJointLatchingBits)) == 0 ? 1 : 0;
      driven_[rig] = enabled_[rig] != 0 && (state.status_bits & hal::kJointStale) == 0 ? 1 : 0;
    }
  }
  return std::all_of(reported_.begin(), reported_.end(), [](std::uint8_t r) { return r != 0; });
}

}  // namespace cambio::control
