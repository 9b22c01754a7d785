#include "cambio/control/joint_loop.hpp"

#include <algorithm>
#include <stdexcept>

namespace cambio::control {

namespace {

constexpr std::uint32_t bit_of(hal::DriveRequest request) {
  return 1u << static_cast<unsigned>(request);
}

}  // namespace

JointLoop::JointLoop(std::vector<hal::JointGroup*> groups,
                     hal::SeqlockChannel<JointTargetFrame>& targets,
                     hal::SeqlockChannel<JointStateFrame>& states, JointLoopParams params)
    : name_(params.name),
      groups_(std::move(groups)),
      targets_(targets),
      states_(states),
      params_(std::move(params)) {
  if (params_.rig_hold != nullptr) rig_hold_slot_ = params_.rig_hold->add_loop();
}

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
  if (!(params_.command_timeout_s > 0.0)) {
    throw std::invalid_argument("joint loop: command timeout must be > 0 s");
  }
  if (!(params_.feedback_timeout_s > 0.0)) {
    throw std::invalid_argument("joint loop: feedback timeout must be > 0 s");
  }
  if (params_.target_indices.empty()) {
    for (int j = 0; j < joint_count_; ++j) params_.target_indices.push_back(j);
    params_.target_count = joint_count_;
  }
  if (static_cast<int>(params_.target_indices.size()) != joint_count_) {
    throw std::invalid_argument("joint loop '" + name_ +
                                "': " + std::to_string(params_.target_indices.size()) +
                                " target indices for " + std::to_string(joint_count_) + " joints");
  }
  for (const int index : params_.target_indices) {
    if (index < 0 || index >= params_.target_count || params_.target_count > kMaxJoints) {
      throw std::invalid_argument("joint loop '" + name_ + "': target index " +
                                  std::to_string(index) + " outside the target frame of " +
                                  std::to_string(params_.target_count) + " joints");
    }
  }
  const auto n = static_cast<std::size_t>(joint_count_);
  state_scratch_.assign(n, hal::JointState{});
  command_scratch_.assign(n, hal::JointCommand{});
  last_position_target_.assign(n, 0.0);
  latched_bits_.assign(n, 0u);
  was_enabled_.assign(n, 0);
}

void JointLoop::activate() {
  std::size_t offset = 0;
  for (hal::JointGroup* group : groups_) {
    const std::size_t n = group->info().joints.size();
    std::int64_t stamp_ns = 0;
    const hal::Status status = group->read(std::span(state_scratch_).subspan(offset, n), stamp_ns);
    if (status == hal::Status::kOk || status == hal::Status::kFault) {
      for (std::size_t j = offset; j < offset + n; ++j) {
        last_position_target_[j] = state_scratch_[j].position_rad;
        was_enabled_[j] = hal::is_enabled(state_scratch_[j].drive_state) ? 1 : 0;
      }
    }
    offset += n;
  }
  pending_requests_.store(0);
  pending_homes_.store(0);
  if (params_.rig_hold != nullptr) params_.rig_hold->set(rig_hold_slot_, false);
  reset_requested_ = false;
  enable_after_reset_ = false;
  fault_latched_since_ns_ = -1;
  if (params_.enable_on_activate) forward(hal::DriveRequest::kEnable);
}

void JointLoop::deactivate() noexcept {
  forward(hal::DriveRequest::kQuickStop);
}

void JointLoop::request(hal::DriveRequest request) noexcept {
  pending_requests_.fetch_or(bit_of(request), std::memory_order_acq_rel);
}

bool JointLoop::request_home(int joint) noexcept {
  static_assert(kMaxJoints <= 64, "one bit per joint");
  if (joint < 0 || joint >= joint_count_) return false;
  pending_homes_.fetch_or(std::uint64_t{1} << joint, std::memory_order_acq_rel);
  return true;
}

void JointLoop::forward_home(std::uint64_t joints) noexcept {
  int first = 0;
  for (hal::JointGroup* group : groups_) {
    const auto n = static_cast<int>(group->info().joints.size());
    for (int k = 0; k < n; ++k) {
      if ((joints >> (first + k) & 1u) == 0) continue;
      if (group->request(hal::DriveRequest::kHome, k) == hal::Status::kRejected) {
        last_refused_home_.store(first + k, std::memory_order_relaxed);
        homes_refused_.fetch_add(1, std::memory_order_relaxed);
      }
    }
    first += n;
  }
}

void JointLoop::recover_if_asked(bool fault_latched, std::int64_t now_ns) noexcept {
  if (!fault_latched) {
    fault_latched_since_ns_ = -1;
    return;
  }
  if (fault_latched_since_ns_ < 0) fault_latched_since_ns_ = now_ns;
  const auto delay_ns = static_cast<std::int64_t>(params_.fault_recovery_delay_s * 1e9);
  if (reset_requested_ ||
      fault_recoveries_.load(std::memory_order_relaxed) >=
          static_cast<std::uint64_t>(std::max(params_.max_fault_recoveries, 0)) ||
      now_ns - fault_latched_since_ns_ < delay_ns) {
    return;
  }
  // As an operator would: reset, then enable once every drive is out of its fault; each joint
  // is enabled where it stands (step 3), so recovery never jumps to the target held before.
  apply_requests(bit_of(hal::DriveRequest::kFaultReset) | bit_of(hal::DriveRequest::kEnable));
  fault_recoveries_.fetch_add(1, std::memory_order_relaxed);
  fault_latched_since_ns_ = now_ns;
}

void JointLoop::forward(hal::DriveRequest request) noexcept {
  for (hal::JointGroup* group : groups_) (void)group->request(request);
}

void JointLoop::apply_requests(std::uint32_t pending) noexcept {
  // "Reset, then enable" asked together: a drive takes one request at a time (a controlword),
  // so the enable waits until every drive has come out of its fault (read_groups()).
  if ((pending & bit_of(hal::DriveRequest::kFaultReset)) != 0) {
    forward(hal::DriveRequest::kFaultReset);
    reset_requested_ = true;
    if ((pending & bit_of(hal::DriveRequest::kEnable)) != 0) {
      enable_after_reset_ = true;
      pending &= ~bit_of(hal::DriveRequest::kEnable);
    }
  }
  if ((pending & bit_of(hal::DriveRequest::kQuickStop)) != 0) {
    forward(hal::DriveRequest::kQuickStop);
  }
  if ((pending & bit_of(hal::DriveRequest::kDisable)) != 0) {
    forward(hal::DriveRequest::kDisable);
  }
  // Before enable: a joint that must home is homed before anything drives it.
  if ((pending & bit_of(hal::DriveRequest::kHome)) != 0) forward(hal::DriveRequest::kHome);
  if ((pending & bit_of(hal::DriveRequest::kEnable)) != 0) forward(hal::DriveRequest::kEnable);
}

hal::Status JointLoop::read_groups(std::int64_t now_ns) noexcept {
  hal::Status result = hal::Status::kOk;
  std::size_t offset = 0;
  std::int64_t newest_stamp_ns = 0;
  for (hal::JointGroup* group : groups_) {
    const std::size_t n = group->info().joints.size();
    std::int64_t stamp_ns = 0;
    result =
        hal::worst(result, group->read(std::span(state_scratch_).subspan(offset, n), stamp_ns));
    offset += n;
  }
  const auto feedback_timeout_ns = static_cast<std::int64_t>(params_.feedback_timeout_s * 1e9);
  bool any_fault_now = false;
  for (std::size_t j = 0; j < state_scratch_.size(); ++j) {
    hal::JointState& state = state_scratch_[j];
    if (now_ns - state.stamp_ns > feedback_timeout_ns) state.status_bits |= hal::kJointStale;
    if (hal::is_faulted(state.drive_state)) state.status_bits |= hal::kJointFault;
    if (!hal::is_enabled(state.drive_state)) state.status_bits |= hal::kJointNotEnabled;
    const std::uint32_t latching = state.status_bits & hal::kJointLatchingBits;
    any_fault_now = any_fault_now || latching != 0;
    latched_bits_[j] |= latching;
    newest_stamp_ns = std::max(newest_stamp_ns, state.stamp_ns);
  }
  // A reset clears the loop's latches only once every drive has come out of its fault (the
  // request may take cycles to reach them); until then the latch stands.
  if (reset_requested_ && !any_fault_now) {
    std::fill(latched_bits_.begin(), latched_bits_.end(), 0u);
    reset_requested_ = false;
    // Joints whose drive rebooted lost their reference: homed (if they home) before enabling.
    if (params_.home_after_reboot) forward(hal::DriveRequest::kHome);
    if (enable_after_reset_) forward(hal::DriveRequest::kEnable);
    enable_after_reset_ = false;
  }
  for (std::size_t j = 0; j < state_scratch_.size(); ++j) {
    state_scratch_[j].status_bits |= latched_bits_[j];
  }
  state_frame_.stamp_ns = newest_stamp_ns;
  return result;
}

hal::Status JointLoop::update(const hal::LoopTick& tick) noexcept {
  if (const std::uint32_t pending = pending_requests_.exchange(0, std::memory_order_acq_rel)) {
    apply_requests(pending);
  }
  if (const std::uint64_t homes = pending_homes_.exchange(0, std::memory_order_acq_rel)) {
    forward_home(homes);
  }

  // 1-2. Read, flag stale readings, latch faults, publish.
  hal::Status result = read_groups(tick.now_ns);
  bool fault_latched = false;
  bool feedback_stale = false;
  for (std::size_t j = 0; j < state_scratch_.size(); ++j) {
    fault_latched = fault_latched || latched_bits_[j] != 0;
    feedback_stale = feedback_stale || (state_scratch_[j].status_bits & hal::kJointStale) != 0;
  }
  // Another loop of the rig holding holds this one too (rig_hold.hpp).
  bool holding = fault_latched || feedback_stale;
  if (params_.rig_hold != nullptr) {
    params_.rig_hold->set(rig_hold_slot_, holding);
    holding = holding || params_.rig_hold->others_holding(rig_hold_slot_);
  }
  if (fault_latched) result = hal::worst(result, hal::Status::kFault);
  recover_if_asked(fault_latched, tick.now_ns);
  if (feedback_stale) {
    result = hal::worst(result, hal::Status::kStale);
    feedback_stale_cycles_.fetch_add(1, std::memory_order_relaxed);
  }
  if (holding) fault_hold_cycles_.fetch_add(1, std::memory_order_relaxed);
  state_frame_.count = joint_count_;
  state_frame_.holding = holding;
  state_frame_.fault_latched = fault_latched;
  std::copy(state_scratch_.begin(), state_scratch_.end(), state_frame_.states.begin());
  states_.write(state_frame_);

  // 3. The newest targets (a torn read keeps the last clean copy); hold if missing or stale.
  (void)targets_.read(targets_frame_);
  const bool fresh = !holding && targets_.version() > 0 &&
                     targets_frame_.count == params_.target_count &&
                     static_cast<double>(tick.now_ns - targets_frame_.stamp_ns) * 1e-9 <=
                         params_.command_timeout_s;
  if (!fresh && !holding) {
    (targets_.version() > 0 ? stale_cycles_ : awaiting_targets_cycles_)
        .fetch_add(1, std::memory_order_relaxed);
  }

  for (std::size_t j = 0; j < static_cast<std::size_t>(joint_count_); ++j) {
    const hal::JointLimits& limits = limits_[j];
    const hal::JointState& state = state_scratch_[j];
    const bool enabled = hal::is_enabled(state.drive_state);
    const bool just_enabled = enabled && was_enabled_[j] == 0;
    was_enabled_[j] = enabled ? 1 : 0;
    hal::JointCommand command;
    if (!enabled || just_enabled) {
      // Not driven, or the first cycle driven: the target is where the joint is, so enabling
      // (now or later) never jumps to an old target.
      command = {hal::CommandMode::kPosition, state.position_rad, 0.0, 0.0};
      last_position_target_[j] = state.position_rad;
    } else if (!fresh) {
      command = {hal::CommandMode::kPosition, last_position_target_[j], 0.0, 0.0};
    } else {
      command = targets_frame_.commands[static_cast<std::size_t>(params_.target_indices[j])];
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
      last_position_target_[j] = state.position_rad;
    }
    command_scratch_[j] = command;
  }

  // 4. Send, then let the groups latch this cycle's targets together.
  std::size_t offset = 0;
  for (hal::JointGroup* group : groups_) {
    const std::size_t n = group->info().joints.size();
    result = hal::worst(result, group->write(std::span(command_scratch_).subspan(offset, n)));
    offset += n;
  }
  for (hal::JointGroup* group : groups_) result = hal::worst(result, group->sync());
  return result;
}

}  // namespace cambio::control
