#pragma once

#include <cstdint>

#include "cambio/control/joint_trajectory.hpp"
#include "cambio/hal/seqlock_channel.hpp"

namespace cambio::control {

/// A loop's inbox of joint trajectories from a latest-value channel. A trajectory is 17 KB: it
/// is copied only when the channel holds a new one (an unwritten channel is at version 0), not
/// every cycle, and each trajectory (by its sequence number, 0 meaning none) is taken once.
/// Real-time safe.
class TrajectoryInbox {
 public:
  /// Configure time; null: no trajectories.
  void set_channel(const hal::SeqlockChannel<JointTrajectory>* channel) { channel_ = channel; }

  /// True when a trajectory not taken before has arrived: it is then latest().
  bool take_new() noexcept {
    std::uint64_t version = 0;
    if (channel_ == nullptr || channel_->version() == version_ ||
        !channel_->read(latest_, &version)) {
      return false;
    }
    version_ = version;
    if (latest_.sequence == 0 || latest_.sequence == last_sequence_) return false;
    last_sequence_ = latest_.sequence;
    return true;
  }

  /// The newest trajectory read from the channel.
  const JointTrajectory& latest() const { return latest_; }

 private:
  const hal::SeqlockChannel<JointTrajectory>* channel_ = nullptr;
  JointTrajectory latest_{};
  std::uint64_t last_sequence_ = 0;
  std::uint64_t version_ = 0;  ///< The channel's version last read.
};

}  // namespace cambio::control
