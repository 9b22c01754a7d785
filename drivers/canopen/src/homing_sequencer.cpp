#include "cambio/canopen/homing_sequencer.hpp"

#include <cstdio>

namespace cambio::canopen {

void HomingSequencer::start(int node_id, int method, std::int64_t homing_timeout_ns,
                            std::int64_t step_timeout_ns, cia402::Mode cyclic_mode,
                            std::int64_t now_ns) {
  client_ = SdoClient(node_id);
  method_ = method;
  cyclic_mode_ = cyclic_mode;
  homing_timeout_ns_ = homing_timeout_ns;
  step_timeout_ns_ = step_timeout_ns;
  state_ = State::kRunning;
  pending_ = false;
  duration_s_ = 0.0;
  homing_since_ns_ = 0;
  statusword_count_ = 0;
  last_statusword_ = 0;
  error_ = {};
  error_.node_id = node_id;
  enter(Step::kDisabling, now_ns);
}

void HomingSequencer::enter(Step step, std::int64_t now_ns) {
  step_ = step;
  step_since_ns_ = now_ns;
  switch (step) {
    case Step::kDisabling:
    case Step::kStopping:
      controlword_ = cia402::kControlDisableVoltage;
      return;
    case Step::kModeHoming:
      write_mode(cia402::Mode::kHoming, now_ns);
      return;
    case Step::kEnabling:
      return;  // The controlword follows the statusword (on_statusword).
    case Step::kHoming:
      controlword_ = cia402::kControlEnableOperation | cia402::kControlHomingStart;
      homing_since_ns_ = now_ns;
      answers_since_start_ = 0;
      return;
    case Step::kModeCyclic:
      write_mode(cyclic_mode_, now_ns);
      return;
  }
}

void HomingSequencer::write_mode(cia402::Mode mode, std::int64_t now_ns) {
  mode_byte_[0] = static_cast<std::uint8_t>(static_cast<std::int8_t>(mode));
  pending_frame_ =
      client_.start_download(cia402::kModesOfOperation, mode_byte_, now_ns, step_timeout_ns_);
  pending_ = true;
}

void HomingSequencer::keep(std::uint16_t statusword) {
  if (statusword_count_ > 0 && statuswords_[statusword_count_ - 1] == statusword) return;
  if (statusword_count_ < statuswords_.size()) statuswords_[statusword_count_++] = statusword;
}

void HomingSequencer::on_statusword(std::uint16_t statusword, std::int64_t now_ns) {
  if (state_ != State::kRunning) return;
  last_statusword_ = statusword;
  const hal::DriveState state = cia402::drive_state_of(statusword);
  if (step_ >= Step::kEnabling) keep(statusword);
  if (hal::is_faulted(state)) {
    fail(HomingFailure::kDriveFault, now_ns);
    return;
  }
  switch (step_) {
    case Step::kDisabling:
      if (state == hal::DriveState::kSwitchOnDisabled) enter(Step::kModeHoming, now_ns);
      return;
    case Step::kModeHoming:
    case Step::kModeCyclic:
      return;  // Waiting for the SDO answer.
    case Step::kEnabling:
      if (state == hal::DriveState::kOperationEnabled) {
        enter(Step::kHoming, now_ns);
      } else {
        controlword_ = cia402::controlword_toward(state, hal::DriveRequest::kEnable, controlword_);
      }
      return;
    case Step::kHoming: {
      ++answers_since_start_;
      duration_s_ = static_cast<double>(now_ns - homing_since_ns_) * 1e-9;
      if ((statusword & cia402::kStatusHomingError) != 0) {
        fail(HomingFailure::kHomingError, now_ns);
        return;
      }
      if (state != hal::DriveState::kOperationEnabled) {
        fail(HomingFailure::kNotEnabled, now_ns);
        return;
      }
      constexpr std::uint16_t kCompleted =
          cia402::kStatusHomingAttained | cia402::kStatusTargetReached;
      // The answer to the SYNC that carried bit 4 may still show an earlier homing's bits.
      if (answers_since_start_ >= 2 && (statusword & kCompleted) == kCompleted) {
        enter(Step::kStopping, now_ns);
      }
      return;
    }
    case Step::kStopping:
      if (state == hal::DriveState::kSwitchOnDisabled) enter(Step::kModeCyclic, now_ns);
      return;
  }
}

void HomingSequencer::on_sdo_frame(const hal::CanFrame& frame, std::int64_t now_ns) {
  if (state_ != State::kRunning || client_.state() != SdoClient::State::kBusy) return;
  hal::CanFrame reply;
  if (client_.on_frame(frame, now_ns, reply)) {
    pending_frame_ = reply;
    pending_ = true;
  }
  if (client_.state() == SdoClient::State::kAborted) {
    fail_sdo();
  } else if (client_.state() == SdoClient::State::kDone) {
    if (step_ == Step::kModeHoming) {
      enter(Step::kEnabling, now_ns);
    } else if (step_ == Step::kModeCyclic) {
      state_ = State::kDone;
    }
  }
}

void HomingSequencer::on_boot_up(std::int64_t now_ns) {
  fail(HomingFailure::kDriveRebooted, now_ns);
}

void HomingSequencer::poll(std::int64_t now_ns) {
  if (state_ != State::kRunning) return;
  if (client_.state() == SdoClient::State::kBusy) {
    hal::CanFrame reply;
    if (client_.poll(now_ns, reply)) {
      pending_frame_ = reply;  // Tell the drive, so it does not wait for the rest.
      pending_ = true;
      fail_sdo();
    }
    return;
  }
  const std::int64_t in_step_ns = now_ns - step_since_ns_;
  switch (step_) {
    case Step::kDisabling:
    case Step::kStopping:
      if (in_step_ns > step_timeout_ns_) fail(HomingFailure::kNotDisabled, now_ns);
      return;
    case Step::kEnabling:
      if (in_step_ns > step_timeout_ns_) fail(HomingFailure::kNotEnabled, now_ns);
      return;
    case Step::kHoming:
      if (in_step_ns > homing_timeout_ns_) {
        duration_s_ = static_cast<double>(in_step_ns) * 1e-9;
        fail(HomingFailure::kTimeout, now_ns);
      }
      return;
    case Step::kModeHoming:
    case Step::kModeCyclic:
      return;
  }
}

void HomingSequencer::stop(HomingFailure failure, std::int64_t now_ns) {
  fail(failure, now_ns);
}

void HomingSequencer::fail(HomingFailure failure, std::int64_t now_ns) {
  if (state_ != State::kRunning) return;
  if (step_ == Step::kHoming) duration_s_ = static_cast<double>(now_ns - homing_since_ns_) * 1e-9;
  std::snprintf(error_.text.data(), error_.text.size(),
                "node %d: homing method %d: %s after %.3f s, statusword 0x%04X", client_.node_id(),
                method_, to_string(failure), duration_s_, static_cast<unsigned>(last_statusword_));
  error_.failure = failure;
  // Stop searching; a rebooted drive is already disabled and back in its defaults.
  controlword_ = cia402::kControlDisableVoltage;
  state_ = State::kFailed;
}

void HomingSequencer::fail_sdo() {
  std::array<char, 128> failure{};
  client_.describe_failure(failure);
  std::snprintf(error_.text.data(), error_.text.size(), "node %d: homing method %d: %s: %s",
                client_.node_id(), method_, to_string(HomingFailure::kSdoFailed), failure.data());
  error_.failure = HomingFailure::kSdoFailed;
  controlword_ = cia402::kControlDisableVoltage;
  state_ = State::kFailed;
}

}  // namespace cambio::canopen
