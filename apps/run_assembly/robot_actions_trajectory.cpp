#include <algorithm>
#include <vector>

#include "cambio/config/echoed_text.hpp"
#include "robot_action_text.hpp"
#include "robot_actions.hpp"

// RobotActions' joint trajectories: the joints named, routed to the loop that drives them, checked
// against the limits and where the joints are now, then sent on that loop's trajectory channel.

namespace cambio::app {

using action_text::refused;

void RobotActions::set_measured_joints(control::BelievedJoints measured) {
  std::lock_guard lock(mutex_);
  measured_rad_.assign(static_cast<std::size_t>(measured.rig_joint_count()), 0.0);
  measured_ = std::make_unique<control::BelievedJoints>(std::move(measured));
}

behaviour::ActionResult RobotActions::follow_trajectory(std::span<const std::string> names,
                                                        control::JointTrajectory trajectory) {
  if (names.size() != static_cast<std::size_t>(trajectory.joint_count) || names.empty() ||
      names.size() > static_cast<std::size_t>(control::JointTrajectory::kMaxJoints)) {
    return refused(std::to_string(names.size()) + " joints: a trajectory moves 1 to " +
                   std::to_string(control::JointTrajectory::kMaxJoints));
  }
  std::vector<hal::JointLimits> limits;
  std::vector<std::string> joint_names;
  std::size_t head_joints = 0;
  for (std::size_t j = 0; j < names.size(); ++j) {
    std::string why;
    const auto joint = find_joint(names[j], why);
    if (joint == joints_.end()) return refused(why);
    if (std::find(names.begin(), names.begin() + static_cast<std::ptrdiff_t>(j), names[j]) !=
        names.begin() + static_cast<std::ptrdiff_t>(j)) {
      return refused("joint " + config::in_quotes(names[j]) + " is named twice");
    }
    trajectory.joint_rig_index[j] = static_cast<int>(joint - joints_.begin());
    limits.push_back(joint->limits);
    joint_names.push_back(joint->name);
    if (joint->head) ++head_joints;
  }
  if (head_joints != 0 && head_joints != names.size()) {
    return refused(
        "a trajectory moves the head's joints or the arms', not both (the gaze loop and the arm "
        "loop each take their own)");
  }
  const bool head = head_joints != 0;
  hal::SeqlockChannel<control::JointTrajectory>* channel =
      head ? channels_.head_trajectories : channels_.arm_trajectories;
  if (channel == nullptr) {
    return refused(head ? "this run takes no head trajectories"
                        : "this run has no arm controller to take the trajectory");
  }
  std::lock_guard lock(mutex_);
  if (!measured_ || !measured_->read(measured_rad_)) {
    return refused("the joints have not reported where they are yet");
  }
  std::vector<double> measured;
  for (std::size_t j = 0; j < names.size(); ++j) {
    measured.push_back(measured_rad_[static_cast<std::size_t>(trajectory.joint_rig_index[j])]);
  }
  std::string why = control::check_joint_trajectory(trajectory, limits, measured, joint_names);
  if (!why.empty()) return refused(why);
  trajectory.sequence = ++trajectory_sequence_;
  channel->write(trajectory);
  return {true, {}};
}

std::uint64_t RobotActions::trajectories_sent() const {
  std::lock_guard lock(mutex_);
  return trajectory_sequence_;
}

}  // namespace cambio::app
