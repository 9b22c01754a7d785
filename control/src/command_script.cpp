#include "cambio/control/command_script.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace cambio::control {

CommandScript::CommandScript(std::vector<Entry> entries, hal::SeqlockChannel<GazeCommand>& commands,
                             hal::SeqlockChannel<ArmCommand>* arm_commands)
    : entries_(std::move(entries)),
      sent_ns_(entries_.size(), -1),
      commands_(commands),
      arm_commands_(arm_commands) {
  double previous_s = 0.0;
  for (std::size_t i = 0; i < entries_.size(); ++i) {
    const double at_s = entries_[i].at_s;
    if (!std::isfinite(at_s) || at_s < previous_s) {
      throw std::invalid_argument("command script: entry " + std::to_string(i) +
                                  " has a time that is negative, not finite or earlier than the "
                                  "one before it");
    }
    previous_s = at_s;
    if (entries_[i].to_arms && arm_commands_ == nullptr) {
      throw std::invalid_argument("command script: entry " + std::to_string(i) +
                                  " is an arm command, and the run has no arms to send it to");
    }
  }
}

void CommandScript::activate() {
  next_ = 0;
  started_ = false;
  std::fill(sent_ns_.begin(), sent_ns_.end(), -1);
}

hal::Status CommandScript::update(const hal::LoopTick& tick) noexcept {
  if (!started_) {
    started_ = true;
    start_ns_ = tick.now_ns;
  }
  const double run_s = static_cast<double>(tick.now_ns - start_ns_) * 1e-9;
  // Several commands due in one cycle: the newest wins (a latest-value channel), all are logged.
  // Gaze and arm commands go to their own channels: one of each may be sent in a cycle.
  bool sent = false;
  bool arm_sent = false;
  GazeCommand command;
  ArmCommand arm_command;
  while (next_ < entries_.size() && entries_[next_].at_s <= run_s + 1e-9) {
    const Entry& entry = entries_[next_];
    if (entry.to_arms) {
      arm_command = entry.arm_command;
      arm_command.sequence = ++arm_sequence_;
      arm_sent = true;
    } else {
      command = entry.command;
      command.sequence = ++sequence_;
      sent = true;
    }
    sent_ns_[next_] = tick.now_ns;
    ++next_;
  }
  if (sent) commands_.write(command);
  if (arm_sent) arm_commands_->write(arm_command);
  return sent || arm_sent ? hal::Status::kOk : hal::Status::kNoNewData;
}

}  // namespace cambio::control
