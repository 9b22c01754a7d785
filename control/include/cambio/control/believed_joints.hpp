#pragma once

#include <span>
#include <vector>

#include "cambio/control/joint_frames.hpp"
#include "cambio/hal/seqlock_channel.hpp"

namespace cambio::control {

/// The Control Module's belief about its joints (the paper's CM keeps its own state, apart from
/// the world's truth): the encoder readings every joint loop publishes, merged into rig order.
/// The constructor allocates; read() is real-time safe (no allocation, no locks, bounded).
class BelievedJoints {
 public:
  /// One joint loop's published states; `rig_indices[i]` is the rig-order index of its i-th
  /// joint.
  struct Source {
    const hal::SeqlockChannel<JointStateFrame>* states = nullptr;
    std::vector<int> rig_indices;
  };

  /// Throws std::invalid_argument for a null channel or an index outside [0, rig_joint_count).
  BelievedJoints(std::vector<Source> sources, int rig_joint_count);

  /// Writes the newest reading of every joint into `q_rig_rad` (size rig_joint_count()); a joint
  /// no loop has reported yet keeps the value `q_rig_rad` held. Returns true once every joint has
  /// been reported at least once. A torn read keeps the source's last clean frame.
  bool read(std::span<double> q_rig_rad) noexcept;

  /// A joint loop holds (fault latched or feedback stale) in the newest frames.
  bool holding() const { return holding_; }
  /// The joint follows its targets in the newest frame: reported, operation enabled, fresh and
  /// fault-free. A joint that does not (disabled, homing, faulted) ignores what it is sent.
  bool driven(int rig_index) const { return driven_[static_cast<std::size_t>(rig_index)] != 0; }
  /// The joint's drive is enabled and fault-free in the newest frame, its reading fresh or not.
  bool enabled(int rig_index) const { return enabled_[static_cast<std::size_t>(rig_index)] != 0; }
  int rig_joint_count() const { return rig_joint_count_; }

 private:
  std::vector<Source> sources_;
  std::vector<JointStateFrame> frames_;  // The last clean frame of each source.
  std::vector<std::uint8_t> reported_;   // Per rig joint.
  std::vector<std::uint8_t> driven_;     // Per rig joint, in the newest frames.
  std::vector<std::uint8_t> enabled_;    // Per rig joint, in the newest frames.
  int rig_joint_count_ = 0;
  bool holding_ = false;
};

}  // namespace cambio::control
