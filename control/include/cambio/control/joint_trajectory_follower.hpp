#pragma once

#include <array>
#include <cstdint>
#include <span>

#include "cambio/control/joint_trajectory.hpp"

namespace cambio::control {

/// A loop's side of a JointTrajectory: takes one from where the joints are commanded and writes
/// the commands along it each cycle, then holds its last point. The loop decides whether the
/// trajectory's joints are its own before start(). Real-time: no allocation.
class JointTrajectoryFollower {
 public:
  /// Starts `trajectory` at `now_ns` from the commands `q_command_tree` (tree order) of its
  /// joints; `rig_to_tree` maps its rig indices to tree indices (valid, checked by the caller).
  void start(const JointTrajectory& trajectory, std::span<const int> rig_to_tree,
             std::span<const double> q_command_tree, std::int64_t now_ns) noexcept;
  /// Writes the trajectory's commands at `now_ns` into `q_command_tree`; returns false (and stops)
  /// on the cycle that writes its last point.
  bool step(std::int64_t now_ns, std::span<double> q_command_tree) noexcept;
  /// Stops where the commands are (a new command, a hold of the drives).
  void stop() noexcept { active_ = false; }
  bool active() const noexcept { return active_; }
  /// Whether the running trajectory commands this joint (tree index).
  bool drives(int tree_index) const noexcept;
  /// Trajectories started, finished to their last point, and stopped before it.
  std::uint64_t started() const noexcept { return started_; }
  std::uint64_t finished() const noexcept { return finished_; }

 private:
  JointTrajectory trajectory_{};
  std::array<int, JointTrajectory::kMaxJoints> tree_index_{};
  std::array<double, JointTrajectory::kMaxJoints> start_rad_{};
  std::array<double, JointTrajectory::kMaxJoints> q_rad_{};
  std::int64_t start_ns_ = 0;
  bool active_ = false;
  std::uint64_t started_ = 0;
  std::uint64_t finished_ = 0;
};

}  // namespace cambio::control
