// The loop-side homing sequence (homing_sequencer.hpp) against a drive played by the test: the
// CiA 402 state machine of cia402.hpp driven by the sequencer's controlwords, SDO answers as
// CiA 301 lays them out, and the homing statusword bits (13 error, 12 attained, 10 target
// reached) the test chooses. Each path ends as CiA 402-2 says: completed, or failed by name.
#include "cambio/canopen/homing_sequencer.hpp"

#include <gtest/gtest.h>

#include <optional>
#include <string>
#include <vector>

namespace cambio::canopen {
namespace {

constexpr int kNode = 3;
constexpr std::int64_t kPeriodNs = 1'000'000;  // 1 kHz.
constexpr std::int64_t kStepTimeoutNs = 20 * kPeriodNs;
constexpr std::int64_t kHomingTimeoutNs = 500 * kPeriodNs;

/// The drive: its CiA 402 state follows the controlwords; its mode follows SDO writes of 0x6060.
struct PlayedDrive {
  hal::DriveState state = hal::DriveState::kOperationEnabled;  // Running CSP when asked.
  std::uint16_t previous_controlword = cia402::kControlEnableOperation;
  int mode = 8;
  std::uint16_t homing_bits = cia402::kStatusHomingAttained | cia402::kStatusTargetReached;
  /// Abort a write of 0x6060 with this code instead of taking it.
  std::optional<std::uint32_t> abort_mode_write;
  std::vector<std::uint16_t> controlwords;  ///< Each one that differs from the one before.
  std::vector<int> modes_written;

  std::uint16_t statusword() const {
    return static_cast<std::uint16_t>(cia402::statusword_of(state) | (mode == 6 ? homing_bits : 0));
  }

  /// One cycle: the RPDO's controlword, then the SDO request if any; returns the SDO answer.
  std::optional<hal::CanFrame> take(HomingSequencer& homing) {
    const std::uint16_t controlword = homing.controlword();
    if (controlwords.empty() || controlwords.back() != controlword) {
      controlwords.push_back(controlword);
    }
    state = cia402::drive_state_after(
        state, cia402::decode_controlword(controlword, previous_controlword));
    previous_controlword = controlword;
    if (!homing.has_pending()) return std::nullopt;
    const hal::CanFrame request = homing.pending_frame();
    homing.on_sent();
    EXPECT_EQ(request.id, 0x600u + kNode);
    EXPECT_EQ(request.data[0] & 0xE0, 0x20) << "a download";
    EXPECT_EQ(request.data[1] | request.data[2] << 8, 0x6060);
    hal::CanFrame answer;
    answer.id = 0x580 + kNode;
    answer.length = 8;
    for (int i = 1; i < 4; ++i) answer.data[i] = request.data[i];
    if (abort_mode_write) {
      answer.data[0] = 0x80;
      for (int i = 0; i < 4; ++i) {
        answer.data[4 + i] = static_cast<std::uint8_t>(*abort_mode_write >> (8 * i));
      }
      return answer;
    }
    mode = static_cast<std::int8_t>(request.data[4]);
    modes_written.push_back(mode);
    answer.data[0] = 0x60;
    return answer;
  }
};

struct HomingRun {
  HomingSequencer homing;
  PlayedDrive drive;
  std::int64_t now_ns = 0;

  HomingRun() {
    homing.start(kNode, 17, kHomingTimeoutNs, kStepTimeoutNs,
                 cia402::Mode::kCyclicSynchronousPosition, now_ns);
  }
  /// One joint-loop cycle: the drive takes this cycle's frames and answers the SYNC.
  void cycle() {
    const std::optional<hal::CanFrame> answer = drive.take(homing);
    now_ns += kPeriodNs;
    if (answer) homing.on_sdo_frame(*answer, now_ns);
    homing.on_statusword(drive.statusword(), now_ns);
    homing.poll(now_ns);
  }
  /// Cycles until the run ends or `cycles` passed; returns the cycles taken.
  int until_done(int cycles = 2000) {
    for (int k = 1; k <= cycles; ++k) {
      cycle();
      if (!homing.running()) return k;
    }
    return -1;
  }
  std::string text() const { return homing.error().text.data(); }
};

using State = HomingSequencer::State;

TEST(HomingSequencer, DisablesSwitchesToMode6EnablesStartsAndGoesBackToCspWhenAttained) {
  HomingRun run;
  // Homing runs for 100 cycles once bit 4 is up; the first answer still shows the bits of an
  // earlier homing (attained, target reached), which must not end this one.
  int homing_cycles = 0;
  for (int k = 0; k < 400 && run.homing.running(); ++k) {
    const bool started = (run.homing.controlword() & cia402::kControlHomingStart) != 0;
    if (started && run.drive.mode == 6) {
      ++homing_cycles;
      run.drive.homing_bits = homing_cycles <= 1     ? run.drive.homing_bits  // Stale.
                              : homing_cycles <= 100 ? std::uint16_t{0}       // In progress.
                                                     : std::uint16_t{0x1400};
    }
    run.cycle();
  }
  ASSERT_EQ(run.homing.state(), State::kDone) << run.text();
  EXPECT_GE(homing_cycles, 100) << "ended on the stale attained bits";
  EXPECT_EQ(run.drive.modes_written, (std::vector<int>{6, 8}));
  EXPECT_EQ(run.drive.controlwords,
            (std::vector<std::uint16_t>{0x0000, 0x0006, 0x0007, 0x000F, 0x001F, 0x0000}));
  EXPECT_EQ(run.drive.state, hal::DriveState::kSwitchOnDisabled) << "ends disabled";
  EXPECT_NEAR(run.homing.duration_s(), 0.1, 0.005);
  // The statuswords from enabling on: ready, switched on, enabled; in progress; attained; off.
  const auto words = run.homing.statuswords();
  ASSERT_FALSE(words.empty());
  EXPECT_EQ(words.back() & 0x4F, 0x40) << "switch on disabled at the end";
  bool saw_progress = false, saw_attained = false;
  for (const std::uint16_t word : words) {
    saw_progress = saw_progress || ((word & 0x6F) == 0x27 && (word & 0x3400) == 0);
    saw_attained = saw_attained || (word & 0x3400) == 0x1400;
  }
  EXPECT_TRUE(saw_progress && saw_attained);
}

TEST(HomingSequencer, TheErrorBitFailsItByNameAndTheDriveIsDisabled) {
  HomingRun run;
  run.drive.homing_bits = 0;
  for (int k = 0; k < 50; ++k) run.cycle();
  ASSERT_TRUE(run.homing.running());
  run.drive.homing_bits = cia402::kStatusHomingError;
  run.cycle();
  ASSERT_EQ(run.homing.state(), State::kFailed);
  EXPECT_EQ(run.homing.error().failure, HomingFailure::kHomingError);
  EXPECT_EQ(run.homing.error().node_id, kNode);
  EXPECT_NE(run.text().find("node 3: homing method 17: homing error (statusword bit 13) after "),
            std::string::npos)
      << run.text();
  EXPECT_NE(run.text().find("statusword 0x2"), std::string::npos) << run.text();
  EXPECT_EQ(run.homing.controlword(), cia402::kControlDisableVoltage);
}

TEST(HomingSequencer, NotCompletedWithinTheRigsTimeoutIsATimeout) {
  HomingRun run;
  run.drive.homing_bits = 0;  // Searching for ever.
  const int cycles = run.until_done();
  EXPECT_EQ(run.homing.error().failure, HomingFailure::kTimeout) << run.text();
  // Disabling, mode 6 and enabling take a few cycles, then the 500 ms timeout.
  EXPECT_GT(cycles, 500);
  EXPECT_LT(cycles, 520);
  EXPECT_NE(run.text().find("homing timeout after 0.50"), std::string::npos) << run.text();
}

TEST(HomingSequencer, ABootUpOrAFaultEndsIt) {
  HomingRun rebooted;
  rebooted.drive.homing_bits = 0;
  for (int k = 0; k < 30; ++k) rebooted.cycle();
  rebooted.homing.on_boot_up(rebooted.now_ns);
  EXPECT_EQ(rebooted.homing.error().failure, HomingFailure::kDriveRebooted);
  EXPECT_NE(rebooted.text().find("drive rebooted while homing"), std::string::npos);

  HomingRun faulted;
  faulted.drive.homing_bits = 0;
  for (int k = 0; k < 30; ++k) faulted.cycle();
  faulted.drive.state = hal::DriveState::kFault;
  faulted.cycle();
  EXPECT_EQ(faulted.homing.error().failure, HomingFailure::kDriveFault);
}

TEST(HomingSequencer, AModeChangeTheDriveRefusesIsReportedWithItsAbortCode) {
  HomingRun run;
  run.drive.abort_mode_write = 0x06090030;
  EXPECT_GT(run.until_done(), 0);
  EXPECT_EQ(run.homing.error().failure, HomingFailure::kSdoFailed);
  EXPECT_NE(run.text().find("node 3: homing method 17: mode change over SDO failed: SDO "
                            "download to 0x6060:00 aborted by the drive: 0x06090030"),
            std::string::npos)
      << run.text();
}

TEST(HomingSequencer, ADriveThatNeverDisablesOrNeverEnablesFailsAfterTheStepTimeout) {
  HomingRun stuck;
  stuck.drive.state = hal::DriveState::kNotReadyToSwitchOn;  // Never reaches switch on disabled.
  const int cycles = stuck.until_done();
  EXPECT_EQ(stuck.homing.error().failure, HomingFailure::kNotDisabled) << stuck.text();
  EXPECT_EQ(cycles, 21);
}

TEST(HomingSequencer, AnSdoAnswerThatNeverComesTimesOutAndTheDriveIsToldWithAnAbort) {
  HomingSequencer homing;
  homing.start(kNode, 33, kHomingTimeoutNs, kStepTimeoutNs,
               cia402::Mode::kCyclicSynchronousVelocity, 0);
  homing.on_statusword(0x0040, kPeriodNs);  // Switch on disabled: the mode write goes out.
  ASSERT_TRUE(homing.has_pending());
  homing.on_sent();
  homing.poll(kPeriodNs + kStepTimeoutNs + 1);
  EXPECT_EQ(homing.state(), State::kFailed);
  EXPECT_EQ(homing.error().failure, HomingFailure::kSdoFailed);
  ASSERT_TRUE(homing.has_pending()) << "the abort";
  EXPECT_EQ(homing.pending_frame().data[0], 0x80);
  EXPECT_NE(std::string(homing.error().text.data()).find("not answered in time"),
            std::string::npos);
}

}  // namespace
}  // namespace cambio::canopen
