#include "cambio/control/joint_trajectory_follower.hpp"

namespace cambio::control {
namespace {
std::size_t at(int i) {
  return static_cast<std::size_t>(i);
}
}  // namespace

void JointTrajectoryFollower::start(const JointTrajectory& trajectory,
                                    std::span<const int> rig_to_tree,
                                    std::span<const double> q_command_tree,
                                    std::int64_t now_ns) noexcept {
  trajectory_ = trajectory;
  for (int j = 0; j < trajectory_.joint_count; ++j) {
    tree_index_[at(j)] = rig_to_tree[at(trajectory_.joint_rig_index[at(j)])];
    start_rad_[at(j)] = q_command_tree[at(tree_index_[at(j)])];
  }
  start_ns_ = now_ns;
  active_ = true;
  ++started_;
}

bool JointTrajectoryFollower::step(std::int64_t now_ns, std::span<double> q_command_tree) noexcept {
  if (!active_) return false;
  const double t_s = static_cast<double>(now_ns - start_ns_) * 1e-9;
  const auto joints = at(trajectory_.joint_count);
  sample_joint_trajectory(trajectory_, std::span(start_rad_).first(joints), t_s,
                          std::span(q_rad_).first(joints));
  for (std::size_t j = 0; j < joints; ++j) q_command_tree[at(tree_index_[j])] = q_rad_[j];
  if (t_s >= trajectory_.duration_s()) {
    active_ = false;
    ++finished_;
  }
  return active_;
}

bool JointTrajectoryFollower::drives(int tree_index) const noexcept {
  if (!active_) return false;
  for (int j = 0; j < trajectory_.joint_count; ++j) {
    if (tree_index_[at(j)] == tree_index) return true;
  }
  return false;
}

}  // namespace cambio::control
