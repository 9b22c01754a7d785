#include "cambio/control/pose_hold_loop.hpp"

#include <algorithm>
#include <stdexcept>

namespace cambio::control {
namespace {

std::size_t at(int index) {
  return static_cast<std::size_t>(index);
}

}  // namespace

PoseHoldLoop::PoseHoldLoop(const hal::HardwareInfo& hardware, const JointTargetFrame& pose,
                           BelievedJoints believed,
                           const std::vector<double>& max_tracking_error_rad,
                           hal::SeqlockChannel<JointTargetFrame>& targets)
    : pose_(pose), believed_(std::move(believed)), frame_(pose), targets_(targets) {
  if (!max_tracking_error_rad.empty() && max_tracking_error_rad.size() != hardware.joints.size()) {
    throw std::invalid_argument("pose hold: " + std::to_string(max_tracking_error_rad.size()) +
                                " tracking error limits for " +
                                std::to_string(hardware.joints.size()) + " joints");
  }
  std::vector<CommandTracking::Joint> tracked;
  for (const auto& group : hardware.groups) {
    for (const auto& name : group.joints) {
      const auto info = std::find_if(hardware.joints.begin(), hardware.joints.end(),
                                     [&](const hal::JointInfo& j) { return j.name == name; });
      if (info == hardware.joints.end()) {
        throw std::invalid_argument("pose hold: group '" + group.name +
                                    "' names an unknown joint '" + name + "'");
      }
      CommandTracking::Joint joint;
      joint.name = name;
      joint.rig = static_cast<int>(tracked.size());
      joint.index = joint.rig;
      if (!max_tracking_error_rad.empty()) {
        joint.max_error_rad =
            max_tracking_error_rad[at(static_cast<int>(info - hardware.joints.begin()))];
      }
      max_velocity_rad_s_.push_back(info->limits.max_velocity_rad_s);
      tracked.push_back(std::move(joint));
    }
  }
  const auto rig_count = static_cast<int>(tracked.size());
  if (pose.count != rig_count || believed_.rig_joint_count() != rig_count) {
    throw std::invalid_argument("pose hold: the pose and the believed joints must hold the rig's " +
                                std::to_string(rig_count) + " joints");
  }
  tracking_ = CommandTracking(name_, std::move(tracked));
  for (int i = 0; i < rig_count; ++i) q_command_rig_.push_back(pose.commands[at(i)].value);
  q_measured_rig_ = q_command_rig_;
}

hal::Status PoseHoldLoop::update(const hal::LoopTick& tick) noexcept {
  (void)believed_.read(q_measured_rig_);
  CommandTracking::Step step = tracking_.step(believed_);
  // It starts, as after a hold, from where the joints are: the pose may be elsewhere.
  if (!started_ && step == CommandTracking::Step::kFollow) step = CommandTracking::Step::kRestart;
  switch (step) {
    case CommandTracking::Step::kFrozen:
      break;
    case CommandTracking::Step::kRestart:
      tracking_.restart(q_command_rig_, q_measured_rig_);
      started_ = true;
      break;
    case CommandTracking::Step::kFaulted:
      write(tick.now_ns);
      return hal::Status::kFault;
    case CommandTracking::Step::kFollow:
      // Back to the pose at the velocity limit (a no-op while the joints are on it).
      for (std::size_t i = 0; i < q_command_rig_.size(); ++i) {
        const double max_step_rad = max_velocity_rad_s_[i] * tick.period_s;
        q_command_rig_[i] +=
            std::clamp(pose_.commands[i].value - q_command_rig_[i], -max_step_rad, max_step_rad);
      }
      if (tracking_.check(q_command_rig_, q_measured_rig_)) {
        tracking_.restart(q_command_rig_, q_measured_rig_);
        write(tick.now_ns);
        return report_fault(tracking_.fault_message());
      }
      break;
  }
  write(tick.now_ns);
  return hal::Status::kOk;
}

void PoseHoldLoop::write(std::int64_t now_ns) noexcept {
  for (std::size_t i = 0; i < q_command_rig_.size(); ++i) {
    frame_.commands[i].value = q_command_rig_[i];
  }
  frame_.stamp_ns = now_ns;
  targets_.write(frame_);
}

}  // namespace cambio::control
