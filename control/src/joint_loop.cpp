#include "cambio/control/joint_loop.hpp"

#include <algorithm>
#include <stdexcept>

namespace cambio::control {

JointLoop::JointLoop(std::vector<hal::JointGroup*> groups,
                     hal::SeqlockChannel<JointTargetFrame>& targets,
                     hal::SeqlockChannel<JointStateFrame>& states, double command_timeout_s)
    : groups_(std::move(groups)),
      targets_(targets),
      states_(states),
      command_timeout_s_(command_timeout_s) {}

void JointLoop::configure() {
  joint_count_ = 0;
  limits_.clear();
  for (const hal::JointGroup* group : groups_) {
    if (group == nullptr) throw std::invalid_argument("joint loop: null joint group");
    const auto& info = group->info();
    if (info.limits.size() != info.joints.size()) {
      throw std::invalid_argument("joint loop: group '" + info.name +
                                  "' has a limit count different from its joint count");
    }
    joint_count_ += static_cast<int>(info.joints.size());
    limits_.insert(limits_.end(), info.limits.begin(), info.limits.end());
  }
  if (joint_count_ > kMaxJoints) {
    throw std::invalid_argument("joint loop: " + std::to_string(joint_count_) +
                                " joints exceed the maximum of " + std::to_string(kMaxJoints));
  }
  if (!(command_timeout_s_ > 0.0)) {
    throw std::invalid_argument("joint loop: command timeout must be > 0 s");
  }
  state_scratch_.resize(static_cast<std::size_t>(joint_count_));
  command_scratch_.resize(static_cast<std::size_t>(joint_count_));
  last_position_target_.assign(static_cast<std::size_t>(joint_count_), 0.0);
}

void JointLoop::activate() {
  std::size_t offset = 0;
  for (hal::JointGroup* group : groups_) {
    const std::size_t n = group->info().joints.size();
    std::int64_t stamp_ns = 0;
    if (group->read(std::span(state_scratch_).subspan(offset, n), stamp_ns) == hal::Status::kOk) {
      for (std::size_t j = offset; j < offset + n; ++j) {
        last_position_target_[j] = state_scratch_[j].position_rad;
      }
    }
    offset += n;
  }
}

hal::Status JointLoop::update(const hal::LoopTick& tick) noexcept {
  hal::Status result = hal::Status::kOk;

  // 1. Read and publish what the encoders say.
  std::size_t offset = 0;
  std::int64_t newest_stamp_ns = 0;
  for (hal::JointGroup* group : groups_) {
    const std::size_t n = group->info().joints.size();
    std::int64_t stamp_ns = 0;
    const hal::Status status = group->read(std::span(state_scratch_).subspan(offset, n), stamp_ns);
    if (status != hal::Status::kOk) result = status;
    newest_stamp_ns = std::max(newest_stamp_ns, stamp_ns);
    offset += n;
  }
  state_frame_.stamp_ns = newest_stamp_ns;
  state_frame_.count = joint_count_;
  std::copy(state_scratch_.begin(), state_scratch_.end(), state_frame_.states.begin());
  states_.write(state_frame_);

  // 2. Take the newest targets; hold position if they are missing or stale.
  JointTargetFrame targets;
  targets_.read(targets);
  const bool fresh =
      targets_.version() > 0 && targets.count == joint_count_ &&
      static_cast<double>(tick.now_ns - targets.stamp_ns) * 1e-9 <= command_timeout_s_;
  if (!fresh) ++stale_cycles_;

  for (std::size_t j = 0; j < static_cast<std::size_t>(joint_count_); ++j) {
    const hal::JointLimits& limits = limits_[j];
    hal::JointCommand command;
    if (!fresh) {
      command = {hal::CommandMode::kPosition, last_position_target_[j]};
    } else {
      command = targets.commands[j];
    }
    // A non-finite target becomes "hold"; positions and velocities are clamped to the limits.
    (void)hal::clamp_command(command, limits);
    if (command.mode == hal::CommandMode::kPosition) {
      // The velocity limit as a ramp: at most max_velocity * period from last cycle's target.
      const double step = limits.max_velocity_rad_s * tick.period_s;
      command.value = std::clamp(command.value, last_position_target_[j] - step,
                                 last_position_target_[j] + step);
      last_position_target_[j] = command.value;
    } else {
      last_position_target_[j] = state_scratch_[j].position_rad;
    }
    command_scratch_[j] = command;
  }

  // 3. Send.
  offset = 0;
  for (hal::JointGroup* group : groups_) {
    const std::size_t n = group->info().joints.size();
    const hal::Status status = group->write(std::span(command_scratch_).subspan(offset, n));
    if (status != hal::Status::kOk) result = status;
    offset += n;
  }
  return result;
}

}  // namespace cambio::control
