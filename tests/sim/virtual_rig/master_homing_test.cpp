// CiA 402 homing end to end: the real master (socketcan backend, homing.hpp) homes the pan-tilt's
// pan on the real virtual rig at activate. The truth is the emulated drive's servo (where the
// joint stands), the closed-form home position, the statusword bits as CiA 402-2 numbers them,
// and the frames the master put on the bus.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <functional>
#include <numbers>
#include <string>
#include <vector>

#include "cambio/canopen/homing.hpp"
#include "master_and_rig.hpp"

namespace cambio::virtual_rig::test {
namespace {

constexpr std::uint32_t kPanNode = 1;

config::ConfigOverride pan_homing(const std::string& settings) {
  return {"joints.pan.can.homing", "{" + settings + "}"};
}
config::ConfigOverride pan_virtual_drive(const std::string& settings) {
  return {"joints.pan.can.virtual_drive", "{" + settings + "}"};
}

bool is_sdo_write(const hal::CanFrame& frame, std::uint16_t index, std::uint32_t value) {
  return frame.id == 0x600 + kPanNode && (frame.data[0] & 0xE0) == 0x20 &&
         (frame.data[1] | frame.data[2] << 8) == index &&
         static_cast<std::uint32_t>(frame.data[4] | frame.data[5] << 8) == value;
}

std::string hex_list(const std::vector<std::uint16_t>& words) {
  std::string text;
  for (const std::uint16_t word : words) {
    char item[8];
    std::snprintf(item, sizeof item, "%04X ", word);
    text += item;
  }
  return text;
}

TEST(MasterHoming, LimitSwitchHomingBeforeAnyCspFrameAndTheJointReadsMinusTheOffset) {
  MasterAndRig m({pan_homing("method: 17, switch_speed_rad_s: 1.0, zero_speed_rad_s: 0.05, "
                             "acceleration_rad_s2: 10, offset_deg: 5, timeout_s: 5"),
                  pan_virtual_drive("home_switch_deg: -20")});
  m.start();
  const canopen::CanJointGroup& group = *m.backend->group("pan_tilt");
  ASSERT_EQ(group.homing_records().size(), 1u);
  const canopen::HomingRecord record = group.homing_records()[0];
  EXPECT_EQ(record.joint, "pan");
  EXPECT_EQ(record.node_id, 1);
  std::printf("method 17 statuswords: %s(%.3f s)\n", hex_list(record.statuswords).c_str(),
              record.duration_s);
  // 20 deg to the switch at 1 rad/s, then off it at 0.05 rad/s.
  EXPECT_GT(record.duration_s, 20.0 * std::numbers::pi / 180.0);
  EXPECT_LT(record.duration_s, 1.5);
  // The homing bits (13, 12, 10) of the last statusword: completed.
  EXPECT_EQ(record.statuswords.back() & 0x3400, 0x1400);

  const double switch_rad = -20.0 * std::numbers::pi / 180.0;
  const double offset_rad = 5.0 * std::numbers::pi / 180.0;
  EXPECT_NEAR(m.drive(0).servo().output_position_rad(), switch_rad, 1e-3);
  EXPECT_EQ(m.drive(0).dictionary().get(canopen::cia402::kModesOfOperation), 8u) << "back to CSP";
  EXPECT_EQ(m.drive(0).drive_state(), hal::DriveState::kSwitchOnDisabled);

  // Frames: mode 6, then bit 4, and no SYNC nor RPDO before the joint loop's first cycle.
  std::size_t mode6 = m.sent.size(), start = m.sent.size(), mode8_after = m.sent.size();
  for (std::size_t i = 0; i < m.sent.size(); ++i) {
    const auto& [frame, received] = m.sent[i];
    if (received) continue;
    EXPECT_NE(frame.id, 0x080u) << "no SYNC while homing";
    EXPECT_NE(frame.id, 0x200u + kPanNode) << "no RPDO while homing";
    if (is_sdo_write(frame, 0x6060, 6) && mode6 == m.sent.size()) mode6 = i;
    if (is_sdo_write(frame, 0x6040, 0x1F)) start = i;
    if (is_sdo_write(frame, 0x6060, 8) && start < i) mode8_after = i;
  }
  EXPECT_LT(mode6, start);
  EXPECT_LT(start, mode8_after);

  // The loop reads the homed position: the home position reads -offset (zero = home + offset).
  (void)m.cycle();
  const auto commands = m.hold_here();
  EXPECT_NEAR(m.states[0].position_rad, -offset_rad, 1e-3);
  ASSERT_GT(m.enable(m.hold_here()), 0);
  for (int k = 0; k < 50; ++k) (void)m.cycle(&commands);
  EXPECT_NEAR(m.drive(0).servo().output_position_rad(), switch_rad, 1e-3) << "enabled, no jump";
  // CSP in the homed frame: 0 is offset beyond the switch.
  std::vector<hal::JointCommand> to_zero = {{hal::CommandMode::kPosition, 0.0, 0.0, 0.0},
                                            commands[1]};
  for (int k = 0; k < 500; ++k) (void)m.cycle(&to_zero);
  EXPECT_NEAR(m.drive(0).servo().output_position_rad(), switch_rad + offset_rad, 1e-3);
  EXPECT_NEAR(m.states[0].position_rad, 0.0, 1e-3);
}

TEST(MasterHoming, IndexPulseHomingEndsOnTheClosedFormPulse) {
  // Pulses every motor turn (2 pi / 50) with one at 3 deg; the pan starts at 0, method 33 goes
  // negative: home = 3 deg + floor((0 - 3 deg) / p) p.
  MasterAndRig m({pan_homing("method: 33, switch_speed_rad_s: 1.0, zero_speed_rad_s: 0.2, "
                             "acceleration_rad_s2: 10, offset_rad: 0, timeout_s: 5"),
                  pan_virtual_drive("index_pulse_deg: 3")});
  m.start();
  const canopen::HomingRecord record = m.backend->group("pan_tilt")->homing_records().at(0);
  std::printf("method 33 statuswords: %s(%.3f s)\n", hex_list(record.statuswords).c_str(),
              record.duration_s);
  const double pitch_rad = 2.0 * std::numbers::pi / 50.0;
  const double index_rad = 3.0 * std::numbers::pi / 180.0;
  const double home_rad = index_rad + std::floor((0.0 - index_rad) / pitch_rad) * pitch_rad;
  EXPECT_NEAR(m.drive(0).servo().output_position_rad(), home_rad, 1e-3);
  (void)m.cycle();
  EXPECT_NEAR(m.states[0].position_rad, 0.0, 1e-3) << "offset 0: home reads 0";
  EXPECT_GT(record.duration_s, std::abs(home_rad) / 0.2);
}

/// activate()'s error for the pan with `homing` on a drive with `virtual_drive`.
std::string activate_error(const std::string& homing, const std::string& virtual_drive,
                           const std::function<void(MasterAndRig&)>& during = {}) {
  MasterAndRig m({pan_homing(homing), pan_virtual_drive(virtual_drive)});
  if (during) m.on_answer = [&m, &during] { during(m); };
  try {
    m.start();
  } catch (const std::exception& error) {
    // Never enabled for CSP: no RPDO nor SYNC went out.
    for (const auto& [frame, received] : m.sent) {
      if (!received) {
        EXPECT_TRUE(frame.id != 0x080u && frame.id != 0x200u + kPanNode);
      }
    }
    EXPECT_NE(m.drive(0).drive_state(), hal::DriveState::kOperationEnabled);
    return error.what();
  }
  return "no error";
}

TEST(MasterHoming, EachFailureIsReportedByNameWithNodeAndJoint) {
  const std::string speeds =
      "switch_speed_rad_s: 3.0, zero_speed_rad_s: 0.05, acceleration_rad_s2: 10, ";
  // No switch wired before the joint's limit: the drive's homing error.
  const std::string error = activate_error("method: 18, " + speeds + "timeout_s: 5", "");
  EXPECT_NE(error.find("node 1 (joint 'pan'): homing method 18: homing error (statusword bit 13)"),
            std::string::npos)
      << error;
  // The index pulse search at 0.05 rad/s takes over a second: a 0.2 s timeout.
  const std::string timeout =
      activate_error("method: 33, " + speeds + "timeout_s: 0.2", "index_pulse_deg: 3");
  EXPECT_NE(timeout.find("node 1 (joint 'pan'): homing method 33: homing timeout"),
            std::string::npos)
      << timeout;
  // The drive power-cycles 0.2 s into homing.
  std::int64_t homing_since_ns = -1;
  const std::string reboot = activate_error(
      "method: 17, " + speeds + "timeout_s: 5", "home_switch_deg: -100", [&](MasterAndRig& m) {
        const bool homing = m.drive(0).dictionary().get(canopen::cia402::kModesOfOperation) == 6 &&
                            m.drive(0).drive_state() == hal::DriveState::kOperationEnabled;
        if (homing && homing_since_ns < 0) homing_since_ns = m.clock.now_ns();
        if (homing && m.clock.now_ns() - homing_since_ns > 200'000'000) {
          m.drive(0).power_on(m.clock.now_ns());
        }
      });
  EXPECT_NE(reboot.find("node 1 (joint 'pan'): homing method 17: drive rebooted while homing"),
            std::string::npos)
      << reboot;
}

TEST(MasterHoming, AMethodTheDriveLacksIsRefusedAtConfigureByName) {
  MasterAndRig m(
      {pan_homing("method: 1, switch_speed_rad_s: 1.0, zero_speed_rad_s: 0.05, "
                  "acceleration_rad_s2: 10, timeout_s: 5")});
  try {
    m.backend->configure();
    FAIL() << "configured";
  } catch (const std::exception& error) {
    const std::string text = error.what();
    EXPECT_NE(text.find("joint 'pan': homing method 1 refused by the drive"), std::string::npos)
        << text;
    EXPECT_NE(text.find("0x6098:00"), std::string::npos) << text;
    EXPECT_NE(text.find("0x06090030"), std::string::npos) << text;
  }
}

TEST(MasterHoming, ADriveThatRebootsAfterHomingIsNeverDrivenAgainUntilHomed) {
  MasterAndRig m({pan_homing("method: 17, switch_speed_rad_s: 1.0, zero_speed_rad_s: 0.05, "
                             "acceleration_rad_s2: 10, timeout_s: 5"),
                  pan_virtual_drive("home_switch_deg: -10")});
  m.start();
  (void)m.cycle();
  ASSERT_GT(m.enable(m.hold_here()), 0);
  m.drive(0).power_on(m.clock.now_ns());  // Power cycle: the reference is gone.
  for (int k = 0; k < 20; ++k) (void)m.cycle();
  // Recovery as the joint loop does it: fault reset (the drive is configured again), enable.
  ASSERT_EQ(m.group->request(hal::DriveRequest::kFaultReset), hal::Status::kOk);
  for (int k = 0; k < 200; ++k) (void)m.cycle();
  const std::size_t from = m.sent.size();
  ASSERT_EQ(m.group->request(hal::DriveRequest::kEnable), hal::Status::kOk);
  std::vector<hal::JointCommand> far = {{hal::CommandMode::kPosition, 0.5, 0.0, 0.0},
                                        {hal::CommandMode::kPosition, 0.0, 0.0, 0.0}};
  for (int k = 0; k < 100; ++k) (void)m.cycle(&far);
  int pan_rpdos = 0;
  for (std::size_t i = from; i < m.sent.size(); ++i) {
    const auto& [frame, received] = m.sent[i];
    if (received || frame.id != 0x200u + kPanNode) continue;
    ++pan_rpdos;
    EXPECT_EQ(frame.data[0] | frame.data[1] << 8, 0x0000) << "controlword: disable voltage";
  }
  EXPECT_GT(pan_rpdos, 90);
  EXPECT_EQ(m.drive(0).drive_state(), hal::DriveState::kSwitchOnDisabled);
  EXPECT_EQ(m.drive(1).drive_state(), hal::DriveState::kOperationEnabled) << "tilt is driven";
  EXPECT_FALSE(m.backend->group("pan_tilt")->homed(0));
}

/// The distinct controlwords of the pan's RPDOs in `m.sent` from `from`, in order.
std::vector<std::uint16_t> pan_controlwords(const MasterAndRig& m, std::size_t from) {
  std::vector<std::uint16_t> words;
  for (std::size_t i = from; i < m.sent.size(); ++i) {
    const auto& [frame, received] = m.sent[i];
    if (received || frame.id != 0x200u + kPanNode) continue;
    const auto word = static_cast<std::uint16_t>(frame.data[0] | frame.data[1] << 8);
    if (words.empty() || words.back() != word) words.push_back(word);
  }
  return words;
}

/// The values written to 0x6060 (modes of operation) over SDO from `from`, in order.
std::vector<int> pan_mode_writes(const MasterAndRig& m, std::size_t from) {
  std::vector<int> modes;
  for (std::size_t i = from; i < m.sent.size(); ++i) {
    const auto& [frame, received] = m.sent[i];
    if (!received && frame.id == 0x600 + kPanNode && (frame.data[0] & 0xE0) == 0x20 &&
        (frame.data[1] | frame.data[2] << 8) == 0x6060) {
      modes.push_back(static_cast<std::int8_t>(frame.data[4]));
    }
  }
  return modes;
}

constexpr double kDegToRad = std::numbers::pi / 180.0;

/// Cycles holding every joint where it is measured (what the joint loop sends a joint that is
/// not driven) until `done` or `cycles` passed; returns the cycles taken, -1 if never.
int cycle_until(MasterAndRig& m, const std::function<bool()>& done, int cycles) {
  for (int k = 1; k <= cycles; ++k) {
    const auto hold = m.hold_here();
    (void)m.cycle(&hold);
    if (done()) return k;
  }
  return -1;
}

// `home pan` on the console while the loop runs: the pan homes again over its PDOs (the SYNCs
// and the tilt's CSP go on), ends on its switch reading -offset, and is enabled there.
TEST(MasterHoming, HomingOnRequestRunsOverThePdosWhileTheLoopGoesOnAndEnablesWhereItHomed) {
  MasterAndRig m({pan_homing("method: 17, switch_speed_rad_s: 1.0, zero_speed_rad_s: 0.05, "
                             "acceleration_rad_s2: 10, offset_deg: 5, timeout_s: 5"),
                  pan_virtual_drive("home_switch_deg: -20")});
  m.start();
  (void)m.cycle();
  ASSERT_GT(m.enable(m.hold_here()), 0);
  // The pan at +10 deg in its homed frame, the tilt held.
  std::vector<hal::JointCommand> there = {{hal::CommandMode::kPosition, 10 * kDegToRad, 0, 0},
                                          m.hold_here()[1]};
  for (int k = 0; k < 1000; ++k) (void)m.cycle(&there);
  ASSERT_NEAR(m.states[0].position_rad, 10 * kDegToRad, 1e-3);
  const double tilt_rad = m.states[1].position_rad;

  const canopen::CanJointGroup& group = *m.backend->group("pan_tilt");
  const std::size_t from = m.sent.size();
  m.sent.reserve(from + 100'000);
  m.group_allocations = 0;
  ASSERT_EQ(m.group->request(hal::DriveRequest::kHome, 0), hal::Status::kOk);
  EXPECT_EQ(m.group->request(hal::DriveRequest::kHome, 1), hal::Status::kRejected)
      << "the tilt's encoder is absolute";
  int homing_cycles = 0;
  bool tilt_stayed_enabled = true;
  const int cycles = cycle_until(
      m,
      [&] {
        homing_cycles += (m.states[0].status_bits & hal::kJointHoming) != 0 ? 1 : 0;
        tilt_stayed_enabled =
            tilt_stayed_enabled && m.states[1].drive_state == hal::DriveState::kOperationEnabled;
        return homing_cycles > 0 && !group.homing(0) &&
               m.states[0].drive_state == hal::DriveState::kOperationEnabled;
      },
      3000);
  ASSERT_GT(cycles, 0) << "homed and enabled again";
  const std::vector<std::uint16_t> words = pan_controlwords(m, from);
  std::printf("pan RPDO controlwords: %s\n", hex_list(words).c_str());
  // Disable, mode 6, shutdown, switch on, enable, start (bit 4), disable, mode 8, then enabled
  // again by the standing request.
  EXPECT_EQ(words, (std::vector<std::uint16_t>{0x0000, 0x0006, 0x0007, 0x000F, 0x001F, 0x0000,
                                               0x0006, 0x0007, 0x000F}));
  EXPECT_EQ(pan_mode_writes(m, from), (std::vector<int>{6, 8}));
  EXPECT_EQ(m.group_allocations, 0u) << "the loop side homed without allocating";
  EXPECT_TRUE(tilt_stayed_enabled);
  EXPECT_NEAR(m.states[1].position_rad, tilt_rad, 1e-3) << "the tilt held its place";

  const double switch_rad = -20 * kDegToRad;
  EXPECT_NEAR(m.drive(0).servo().output_position_rad(), switch_rad, 1e-3);
  EXPECT_NEAR(m.states[0].position_rad, -5 * kDegToRad, 1e-3) << "the home reads -offset";
  const auto records = group.homing_records();
  ASSERT_EQ(records.size(), 2u);
  EXPECT_FALSE(records[0].on_request);
  const canopen::HomingRecord& again = records[1];
  EXPECT_TRUE(again.on_request);
  EXPECT_EQ(again.joint, "pan");
  std::printf("homing on request, method 17 statuswords: %s(%.3f s)\n",
              hex_list(again.statuswords).c_str(), again.duration_s);
  // 30 deg to the switch at 1 rad/s, then off it at 0.05 rad/s.
  EXPECT_GT(again.duration_s, 30 * kDegToRad);
  EXPECT_LT(again.duration_s, 1.5);
  EXPECT_TRUE(std::any_of(again.statuswords.begin(), again.statuswords.end(), [](std::uint16_t w) {
    return (w & 0x346F) == 0x1427;
  })) << "operation enabled, homing attained and target reached";
  EXPECT_EQ(group.counters().homings, 1u);
  // kJointHoming from the request to the end of the sequence: at least the homing itself.
  EXPECT_GE(homing_cycles, static_cast<int>(again.duration_s * 1000));
  EXPECT_LT(homing_cycles, static_cast<int>(again.duration_s * 1000) + 30);
  // Enabled where it homed: held there, no jump.
  (void)cycle_until(
      m, [] { return false; }, 100);
  EXPECT_NEAR(m.drive(0).servo().output_position_rad(), switch_rad, 1e-3);
}

// A drive that power-cycles while homing on request: the failure is reported by name, the joint
// is never driven (it lost its reference), and once reconfigured by a fault reset a home request
// for every joint that lost its reference homes it again.
TEST(MasterHoming, ARebootWhileHomingOnRequestIsReportedAndAnotherHomeRequestRecoversIt) {
  MasterAndRig m({pan_homing("method: 17, switch_speed_rad_s: 1.0, zero_speed_rad_s: 0.05, "
                             "acceleration_rad_s2: 10, offset_deg: 0, timeout_s: 5"),
                  pan_virtual_drive("home_switch_deg: -30")});
  m.start();
  (void)m.cycle();
  ASSERT_GT(m.enable(m.hold_here()), 0);
  // Off the switch, where homing left it: 30 deg above.
  std::vector<hal::JointCommand> there = {{hal::CommandMode::kPosition, 30 * kDegToRad, 0, 0},
                                          m.hold_here()[1]};
  for (int k = 0; k < 1000; ++k) (void)m.cycle(&there);
  const canopen::CanJointGroup& group = *m.backend->group("pan_tilt");
  std::int64_t homing_since_ns = -1;
  bool rebooted = false;
  m.on_answer = [&] {
    const bool homing = m.drive(0).dictionary().get(canopen::cia402::kModesOfOperation) == 6 &&
                        m.drive(0).drive_state() == hal::DriveState::kOperationEnabled;
    if (homing && homing_since_ns < 0) homing_since_ns = m.clock.now_ns();
    if (homing && !rebooted && m.clock.now_ns() - homing_since_ns > 100'000'000) {
      rebooted = true;
      m.drive(0).power_on(m.clock.now_ns());
    }
  };
  ASSERT_EQ(m.group->request(hal::DriveRequest::kHome, 0), hal::Status::kOk);
  const int until_error = cycle_until(
      m, [&] { return group.last_homing_error().node_id != 0; }, 2000);
  ASSERT_GT(until_error, 0);
  EXPECT_TRUE(rebooted);
  const std::string error = group.last_homing_error().text.data();
  EXPECT_NE(error.find("node 1: homing method 17: drive rebooted while homing after 0.1"),
            std::string::npos)
      << error;
  EXPECT_EQ(group.counters().homing_failures, 1u);
  EXPECT_FALSE(group.homed(0));

  // Reset: the drive is configured again but stays disabled, unhomed, whatever is asked.
  m.on_answer = {};
  ASSERT_EQ(m.group->request(hal::DriveRequest::kFaultReset), hal::Status::kOk);
  (void)cycle_until(
      m, [] { return false; }, 300);
  ASSERT_EQ(group.counters().reconfigurations, 1u);
  ASSERT_EQ(m.group->request(hal::DriveRequest::kEnable), hal::Status::kOk);
  (void)cycle_until(
      m, [] { return false; }, 100);
  EXPECT_EQ(m.drive(0).drive_state(), hal::DriveState::kSwitchOnDisabled);

  // What the joint loop forwards after a reset when fault_recovery.home_after_reboot is set.
  ASSERT_EQ(m.group->request(hal::DriveRequest::kHome), hal::Status::kOk);
  ASSERT_GT(cycle_until(
                m,
                [&] {
                  return group.homed(0) &&
                         m.states[0].drive_state == hal::DriveState::kOperationEnabled;
                },
                5000),
            0);
  EXPECT_NEAR(m.drive(0).servo().output_position_rad(), -30 * kDegToRad, 1e-3);
  EXPECT_NEAR(m.states[0].position_rad, 0.0, 1e-3);
  EXPECT_EQ(group.counters().homings, 1u);
}

// The rig's timeout_s bounds a homing on request as it bounds the one at activate.
TEST(MasterHoming, HomingOnRequestThatOutlastsTheTimeoutFailsAndLeavesTheJointDisabled) {
  MasterAndRig m({pan_homing("method: 17, switch_speed_rad_s: 1.0, zero_speed_rad_s: 0.1, "
                             "acceleration_rad_s2: 30, offset_deg: 0, timeout_s: 0.5"),
                  pan_virtual_drive("home_switch_deg: -5")});
  m.start();
  (void)m.cycle();
  ASSERT_GT(m.enable(m.hold_here()), 0);
  // 65 deg from the switch: 1.1 s at 1 rad/s, over the 0.5 s timeout.
  std::vector<hal::JointCommand> there = {{hal::CommandMode::kPosition, 60 * kDegToRad, 0, 0},
                                          m.hold_here()[1]};
  for (int k = 0; k < 1500; ++k) (void)m.cycle(&there);
  const canopen::CanJointGroup& group = *m.backend->group("pan_tilt");
  ASSERT_EQ(m.group->request(hal::DriveRequest::kHome, 0), hal::Status::kOk);
  ASSERT_GT(cycle_until(
                m, [&] { return group.last_homing_error().node_id != 0; }, 2000),
            0);
  const std::string error = group.last_homing_error().text.data();
  EXPECT_NE(error.find("node 1: homing method 17: homing timeout after 0.50"), std::string::npos)
      << error;
  (void)cycle_until(
      m, [] { return false; }, 200);
  EXPECT_EQ(m.drive(0).drive_state(), hal::DriveState::kSwitchOnDisabled) << "not driven";
  EXPECT_NE(m.states[0].status_bits & hal::kJointNotEnabled, 0u);
  EXPECT_EQ(m.states[0].status_bits & hal::kJointHoming, 0u);
}

}  // namespace
}  // namespace cambio::virtual_rig::test
