#include "cambio/canopen/homing.hpp"

#include <cstdio>

#include "cambio/canopen/cia402.hpp"
#include "cambio/canopen/nmt_master.hpp"
#include "cambio/canopen/sdo_transfer.hpp"

namespace cambio::canopen {

namespace {

std::int64_t to_ns(double seconds) {
  return static_cast<std::int64_t>(std::llround(seconds * 1e9));
}

std::string hex16(std::uint16_t value) {
  char text[8];
  std::snprintf(text, sizeof text, "0x%04X", value);
  return text;
}

/// Enough transitions from any state but fault to operation enabled (2, 3, 4), and then some.
constexpr int kMaxEnableSteps = 6;

class HomingRun {
 public:
  HomingRun(BusPump& pump, const std::string& joint, int node_id, const HomingSettings& homing,
            double sdo_timeout_s)
      : pump_(pump), node_(node_id), homing_(homing), sdo_timeout_s_(sdo_timeout_s) {
    record_.joint = joint;
    record_.node_id = node_id;
    record_.method = homing.method;
    pump_.set_other_frame_handler([this](const hal::CanFrame& frame) {
      if (!frame.extended_id && frame.id == heartbeat_cob_id(node_) &&
          heartbeat_state(frame) == NmtState::kBootUp) {
        rebooted_ = true;
      }
    });
  }

  ~HomingRun() { pump_.set_other_frame_handler({}); }
  HomingRun(const HomingRun&) = delete;
  HomingRun& operator=(const HomingRun&) = delete;

  std::uint16_t read_statusword() {
    const auto statusword = static_cast<std::uint16_t>(
        sdo_read_value(pump_, node_, cia402::kStatusword, sdo_timeout_s_));
    if (record_.statuswords.empty() || record_.statuswords.back() != statusword) {
      record_.statuswords.push_back(statusword);
    }
    return statusword;
  }
  void write_controlword(std::uint16_t controlword) {
    sdo_write_value(pump_, node_, cia402::kControlword, controlword, 2, sdo_timeout_s_);
    controlword_ = controlword;
  }
  void write_mode(cia402::Mode mode) {
    sdo_write_value(pump_, node_, cia402::kModesOfOperation,
                    static_cast<std::uint8_t>(static_cast<std::int8_t>(mode)), 1, sdo_timeout_s_);
  }

  /// Modes of operation 6, then the CiA 402 transitions to operation enabled.
  void enable_in_homing_mode() {
    write_mode(cia402::Mode::kHoming);
    for (int step = 0; step < kMaxEnableSteps; ++step) {
      const std::uint16_t statusword = read_statusword();
      const hal::DriveState state = cia402::drive_state_of(statusword);
      if (hal::is_faulted(state)) fail(HomingFailure::kDriveFault, statusword);
      if (state == hal::DriveState::kOperationEnabled) return;
      write_controlword(
          cia402::controlword_toward(state, hal::DriveRequest::kEnable, controlword_));
    }
    fail(HomingFailure::kNotEnabled, record_.statuswords.back());
  }

  /// Raises bit 4 and follows the statusword to the end.
  void run(double poll_period_s) {
    write_controlword(cia402::kControlEnableOperation | cia402::kControlHomingStart);
    start_ns_ = pump_.clock().now_ns();
    const std::int64_t timeout_ns = to_ns(homing_.timeout_s);
    for (;;) {
      const std::uint16_t statusword = read_statusword();
      record_.duration_s = elapsed_s();
      if (rebooted_) fail(HomingFailure::kDriveRebooted, statusword);
      if (hal::is_faulted(cia402::drive_state_of(statusword))) {
        fail(HomingFailure::kDriveFault, statusword);
      }
      if ((statusword & cia402::kStatusHomingError) != 0) {
        fail(HomingFailure::kHomingError, statusword);
      }
      constexpr std::uint16_t kCompleted =
          cia402::kStatusHomingAttained | cia402::kStatusTargetReached;
      if ((statusword & kCompleted) == kCompleted) return;
      if (pump_.clock().now_ns() - start_ns_ > timeout_ns) {
        fail(HomingFailure::kTimeout, statusword);
      }
      (void)pump_.pump_until([](const hal::CanFrame&) { return false; },
                             [this] { return rebooted_; }, to_ns(poll_period_s));
    }
  }

  /// Bit 4 down, disabled (transition 9: switch on disabled), back in `mode`, its new position.
  void finish(hal::CommandMode mode) {
    write_controlword(cia402::kControlDisableVoltage);
    write_mode(mode == hal::CommandMode::kPosition ? cia402::Mode::kCyclicSynchronousPosition
                                                   : cia402::Mode::kCyclicSynchronousVelocity);
    record_.feedback.statusword = static_cast<std::uint16_t>(
        sdo_read_value(pump_, node_, cia402::kStatusword, sdo_timeout_s_));
    record_.feedback.position_counts =
        sign_extend(sdo_read_value(pump_, node_, cia402::kPositionActualValue, sdo_timeout_s_), 4);
  }

  /// Best effort after a failure: a rebooted drive is already disabled and back in its defaults;
  /// any other is disabled so it stops searching.
  void stop_after_failure() noexcept {
    if (rebooted_) return;
    try {
      write_controlword(cia402::kControlDisableVoltage);
    } catch (const std::exception&) {
      // The failure is what gets reported; a drive that does not answer now is lost anyway.
    }
  }

  [[noreturn]] void fail(HomingFailure failure, std::uint16_t statusword) {
    record_.duration_s = start_ns_ > 0 ? elapsed_s() : 0.0;
    char seconds[32];
    std::snprintf(seconds, sizeof seconds, "%.3f", record_.duration_s);
    std::string message = "node " + std::to_string(node_) + " (joint '" + record_.joint +
                          "'): homing method " + std::to_string(homing_.method) + ": " +
                          to_string(failure);
    if (failure == HomingFailure::kTimeout) {
      message += " (not completed within timeout_s " + std::to_string(homing_.timeout_s) + ")";
    }
    message += std::string(" after ") + seconds + " s, statusword " + hex16(statusword);
    stop_after_failure();
    throw HomingFailed(message, failure, record_);
  }

  double elapsed_s() const {
    return static_cast<double>(pump_.clock().now_ns() - start_ns_) * 1e-9;
  }
  HomingRecord& record() { return record_; }

 private:
  BusPump& pump_;
  int node_;
  HomingSettings homing_;
  double sdo_timeout_s_;
  HomingRecord record_;
  std::uint16_t controlword_ = cia402::kControlDisableVoltage;
  std::int64_t start_ns_ = 0;
  bool rebooted_ = false;
};

}  // namespace

const char* to_string(HomingFailure failure) {
  switch (failure) {
    case HomingFailure::kHomingError:
      return "homing error (statusword bit 13)";
    case HomingFailure::kTimeout:
      return "homing timeout";
    case HomingFailure::kDriveFault:
      return "drive fault while homing";
    case HomingFailure::kDriveRebooted:
      return "drive rebooted while homing";
    case HomingFailure::kNotEnabled:
      return "drive not enabled for homing";
    case HomingFailure::kNotDisabled:
      return "drive did not disable around homing";
    case HomingFailure::kSdoFailed:
      return "mode change over SDO failed";
    case HomingFailure::kStopped:
      return "stopped: the group holds or the bus is down";
  }
  return "homing failed";
}

HomingRecord home_drive(BusPump& pump, const std::string& joint, int node_id,
                        const HomingSettings& homing, hal::CommandMode operation_mode,
                        double sdo_timeout_s, double poll_period_s) {
  HomingRun run(pump, joint, node_id, homing, sdo_timeout_s);
  run.enable_in_homing_mode();
  run.run(poll_period_s);
  run.finish(operation_mode);
  return run.record();
}

}  // namespace cambio::canopen
