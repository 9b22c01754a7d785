// Tests of a rig's CANopen side, from the rig file to the master's check: the loader's syntax of
// the groups' rate and CANopen keys (firmware_config/src/rig_loader.cpp), what reaches the
// master's types (can_rig_from_config), the bus-load model against frame sizes worked out by hand
// from the PDO contents CiA 402 drives are mapped with (pdo_layout.hpp's comment), and the
// socketcan backend's check (can_rig_check.cpp), each problem located at its rig key.
#include <gtest/gtest.h>

#include <algorithm>
#include <numbers>
#include <string>
#include <vector>

#include "cambio/canopen/can_bus_load.hpp"
#include "cambio/canopen/can_rig_check.hpp"
#include "cambio/canopen/can_rig_from_config.hpp"
#include "cambio/config/hardware_description.hpp"
#include "cambio/config/rig_loader.hpp"
#include "rig_test_support.hpp"

namespace cambio::config {
namespace {

using canopen::can_frame_worst_case_bits;
using canopen::CanBusLoad;
using canopen::kMaxCanBusLoad;
using test::describe;
using test::issues_of;
using test::small_rig_with;

/// The worst-case load the socketcan groups of `rig` put on bus `bus`.
CanBusLoad load_on(const RigConfig& rig, const std::string& bus) {
  const canopen::CanRigInfo can_rig = canopen::can_rig_from_config(rig);
  return canopen::can_bus_load(hardware_description(rig), can_rig, *can_rig.find_bus(bus),
                               "socketcan");
}

/// The socketcan backend's check of `yaml` (which must load), each problem located as the
/// application locates it (RigConfig::locate).
std::vector<ConfigIssue> check_issues(const std::string& yaml,
                                      const std::vector<ConfigOverride>& overrides = {}) {
  const RigConfig rig = load_rig_from_string(yaml, "test.yaml", overrides);
  std::vector<ConfigIssue> issues;
  for (auto& problem : canopen::check_can_rig(hardware_description(rig),
                                              canopen::can_rig_from_config(rig), "socketcan")) {
    issues.push_back(rig.locate(problem.key_path, std::move(problem.message)));
  }
  return issues;
}

void expect_single_issue(const std::vector<ConfigIssue>& issues, int line, int column,
                         const std::string& key_path, const std::string& text) {
  ASSERT_EQ(issues.size(), 1u) << describe(issues);
  EXPECT_EQ(issues[0].line, line) << issues[0].to_string();
  EXPECT_EQ(issues[0].column, column) << issues[0].to_string();
  EXPECT_EQ(issues[0].key_path, key_path);
  EXPECT_NE(issues[0].message.find(text), std::string::npos) << issues[0].to_string();
}

/// Worst-case bits of a classic 11-bit-id frame with `n` data bytes, written out: SOF, id, RTR,
/// IDE, r0, DLC (19), data, CRC (15) are stuffed, one stuff bit per 4 bits after the first;
/// CRC delimiter, ACK (2), EOF (7) and the 3-bit interframe space are not.
constexpr int frame_bits(int n) {
  const int stuffed = 19 + 8 * n + 15;
  return stuffed + (stuffed - 1) / 4 + 1 + 2 + 7 + 3;
}

// The frames the model counts, by their data bytes: RPDO1 controlword (2) + target (4),
// TPDO1 statusword (2) + position (4), a 0-byte SYNC and a 1-byte heartbeat.
static_assert(frame_bits(6) == 115 && frame_bits(0) == 55 && frame_bits(1) == 65);

std::vector<ConfigOverride> sets(const std::vector<std::string>& texts) {
  std::vector<ConfigOverride> overrides;
  for (const auto& text : texts) overrides.push_back(parse_override(text));
  return overrides;
}

const std::string kSocketcanHead =
    "  head: {backend: socketcan, joints: [pan, tilt], can_bus: can0";

TEST(CanLoad, FrameSizesAreTheWorstCaseClosedForm) {
  for (int n = 0; n <= 8; ++n) EXPECT_EQ(can_frame_worst_case_bits(n), frame_bits(n)) << n;
  EXPECT_EQ(can_frame_worst_case_bits(8), 135);
}

TEST(CanLoad, TwoPositionDrivesAt1kHzByHand) {
  const RigConfig rig = load_rig_from_string(small_rig_with(25, kSocketcanHead + "}"), "t");
  // Per 1 kHz cycle: 2 drives x (RPDO1 + TPDO1) of 6 bytes, one SYNC; 2 heartbeats per 100 ms.
  const double bit_s = (2 * (115 + 115) + 55) * 1000.0 + 2 * 65 / 0.1;
  EXPECT_EQ(bit_s, 516'300.0);
  const CanBusLoad load = load_on(rig, "can0");
  ASSERT_EQ(load.groups.size(), 1u);
  EXPECT_EQ(load.groups[0].group, "head");
  EXPECT_EQ(load.groups[0].rate_hz, 1000.0);
  EXPECT_EQ(load.groups[0].drives, 2);
  EXPECT_EQ(load.groups[0].bits_per_cycle, 515);
  EXPECT_DOUBLE_EQ(load.bit_s, bit_s);
  EXPECT_DOUBLE_EQ(load.load, bit_s / 1e6);
  EXPECT_LE(load.load, kMaxCanBusLoad);
}

TEST(CanLoad, MappedFeedForwardAndFeedbackAtTheGroupsOwnRate) {
  const RigConfig rig = load_rig_from_string(
      small_rig_with(25, kSocketcanHead +
                             ", rate_hz: 500, can: {heartbeat_period_ms: 50, feedforward: "
                             "[velocity, effort], feedback: [velocity]}}"),
      "t");
  // RPDO2 velocity offset (4) + torque offset (2): 6 bytes, 115 bits; TPDO2 velocity actual
  // (4): 4 bytes, 95 bits. Two drives at 500 Hz and a heartbeat every 50 ms.
  EXPECT_EQ(frame_bits(4), 95);
  const double bit_s = (2 * (115 + 115 + 115 + 95) + 55) * 500.0 + 2 * 65 / 0.05;
  EXPECT_DOUBLE_EQ(load_on(rig, "can0").bit_s, bit_s);
}

TEST(CanLoad, VelocityModeMapsNoVelocityOffset) {
  // pan commanded in velocity (CSV): no velocity offset to map, so no RPDO2; tilt in position
  // (CSP) maps one.
  auto lines = test::kSmallRigLines;
  lines[12] += "\n    servo: {command: velocity}";
  lines[24] = kSocketcanHead + ", rate_hz: 500, can: {feedforward: [velocity]}}";
  const RigConfig rig = load_rig_from_string(test::join_lines(lines), "t");
  const double bit_s = (115 + 115 + (115 + frame_bits(4) + 115) + 55) * 500.0 + 2 * 65 / 0.1;
  EXPECT_DOUBLE_EQ(load_on(rig, "can0").bit_s, bit_s);
  const canopen::CanRigInfo can_rig = canopen::can_rig_from_config(rig);
  EXPECT_EQ(can_rig.find_drive("pan")->mode, hal::CommandMode::kVelocity);
  EXPECT_EQ(can_rig.find_drive("tilt")->mode, hal::CommandMode::kPosition);
}

TEST(CanLoad, GroupsOnOneBusAddUpEachAtItsRate) {
  // pan and tilt in two groups on can0: one at 1 kHz, one at 250 Hz, each with its own SYNC.
  auto lines = test::kSmallRigLines;
  lines[14] = "    group: tilt_group";
  lines[24] =
      "  head: {backend: socketcan, joints: [pan], can_bus: can0}\n"
      "  tilt_group: {backend: socketcan, joints: [tilt], can_bus: can0, rate_hz: 250}";
  const RigConfig rig = load_rig_from_string(test::join_lines(lines), "t");
  const double bit_s = (230 + 55) * 1000.0 + 65 / 0.1 + (230 + 55) * 250.0 + 65 / 0.1;
  const CanBusLoad load = load_on(rig, "can0");
  ASSERT_EQ(load.groups.size(), 2u);
  EXPECT_EQ(load.groups[1].rate_hz, 250.0);
  EXPECT_DOUBLE_EQ(load.bit_s, bit_s);
}

TEST(CanLoad, SimGroupsPutNothingOnTheBus) {
  const RigConfig rig = load_rig_from_string(test::small_rig(), "t");
  EXPECT_TRUE(load_on(rig, "can0").groups.empty());
  EXPECT_EQ(load_on(rig, "can0").load, 0.0);
  EXPECT_TRUE(check_issues(test::small_rig()).empty());
}

TEST(CanLoad, OverloadNamesTheGroupAndTheRateOrBitrateThatFits) {
  // Two drives at 1 kHz on 500 kbit/s: 516300 bit/s, 103.3%; 60% of 500 kbit/s, less 1300 bit/s
  // of heartbeats, carries 515-bit cycles at 580 Hz; 860500 bit/s would carry them at 1 kHz.
  auto lines = test::kSmallRigLines;
  lines[24] = kSocketcanHead + "}";
  lines[33] = "  can0: {interface: can0, bitrate_bit_s: 500000}";
  const auto issues = check_issues(test::join_lines(lines));
  ASSERT_EQ(issues.size(), 1u) << describe(issues);
  const auto& issue = issues[0];
  EXPECT_EQ(issue.key_path, "can_buses.can0.bitrate_bit_s");
  EXPECT_EQ(issue.line, 34);
  EXPECT_EQ(issue.column, 42);
  for (const std::string text :
       {"(head 2 drives at 1000 Hz: 516300 bit/s worst case)", "103.3% load",
        "set groups.head.rate_hz to at most 580 Hz", "raise bitrate_bit_s to at least 860500"}) {
    EXPECT_NE(issue.message.find(text), std::string::npos) << issue.to_string();
  }
}

TEST(GroupKeys, RateAndCanSettingsReachTheMastersTypes) {
  auto lines = test::kSmallRigLines;
  lines[12] =
      "    can: {node_id: 1, gear_ratio: 50, encoder_counts_per_rev: 4096, "
      "following_error_window_deg: 2}";
  lines[24] = kSocketcanHead +
              ", rate_hz: 400, can: {heartbeat_period_ms: 20, stale_after_missed_syncs: 5, "
              "sdo_timeout_ms: 250, feedforward: [effort], feedback: [velocity, effort]}}";
  const RigConfig rig = load_rig_from_string(test::join_lines(lines), "t");
  EXPECT_EQ(hardware_description(rig).find_group("head")->rate_hz, 400.0);
  const canopen::CanRigInfo can_rig = canopen::can_rig_from_config(rig);
  const canopen::CanGroupInfo& head = *can_rig.find_group("head");
  EXPECT_EQ(head.bus, "can0");
  EXPECT_DOUBLE_EQ(head.settings.heartbeat_period_s, 0.02);
  EXPECT_EQ(head.settings.stale_after_missed_syncs, 5);
  EXPECT_DOUBLE_EQ(head.settings.sdo_timeout_s, 0.25);
  EXPECT_FALSE(head.settings.velocity_feedforward);
  EXPECT_TRUE(head.settings.effort_feedforward);
  EXPECT_TRUE(head.settings.velocity_feedback);
  EXPECT_TRUE(head.settings.effort_feedback);
  EXPECT_DOUBLE_EQ(can_rig.find_drive("pan")->following_error_window_rad,
                   2 * std::numbers::pi / 180);
  EXPECT_EQ(can_rig.find_drive("tilt")->following_error_window_rad, 0.0);
  EXPECT_EQ(can_rig.find_drive("tilt")->node_id, 2);
  EXPECT_EQ(can_rig.find_drive("tilt")->gear_ratio, 50.0);
  EXPECT_EQ(can_rig.find_drive("tilt")->encoder_counts_per_rev, 4096);
}

TEST(GroupKeys, DefaultsAreTheMastersAndTheRigWideRate) {
  const RigConfig rig =
      load_rig_from_string(test::small_rig() + "loops:\n  joint: {rate_hz: 300}\n", "t");
  EXPECT_EQ(hardware_description(rig).find_group("head")->rate_hz, 300.0);
  const canopen::CanRigInfo can_rig = canopen::can_rig_from_config(rig);
  const canopen::CanGroupSettings& head = can_rig.find_group("head")->settings;
  const canopen::CanGroupSettings defaults;
  EXPECT_EQ(head.heartbeat_period_s, defaults.heartbeat_period_s);
  EXPECT_EQ(head.stale_after_missed_syncs, defaults.stale_after_missed_syncs);
  EXPECT_EQ(head.sdo_timeout_s, defaults.sdo_timeout_s);
  EXPECT_FALSE(head.velocity_feedforward || head.effort_feedforward || head.velocity_feedback ||
               head.effort_feedback);
}

struct BadGroupKey {
  std::string group_tail;  // After "can_bus: can0" on line 25.
  int column;
  std::string key_path;
  std::string text;
};

TEST(GroupKeys, BadValuesAreRefusedWithTheirPlace) {
  const std::vector<BadGroupKey> cases = {
      {", rate_hz: 0}", 75, "groups.head.rate_hz", "expected a number in [0.1, 100000]"},
      {", can: {heartbeat_period_ms: 0}}", 93, "groups.head.can.heartbeat_period_ms",
       "expected an integer in [1, 65535]"},
      {", can: {stale_after_missed_syncs: 0}}", 98, "groups.head.can.stale_after_missed_syncs",
       "in [1, 1000]"},
      {", can: {sdo_timeout_ms: -1}}", 88, "groups.head.can.sdo_timeout_ms", "in [1, 60000]"},
      {", can: {feedforward: [velocty]}}", 86, "groups.head.can.feedforward[0]",
       "did you mean \"velocity\"?"},
      {", rate_hz: 100, can: {feedback: [effort, effort]}}", 105, "groups.head.can.feedback[1]",
       "at most once, found \"effort\" again"},
      {", can: {heartbeat_ms: 10}}", 72, "groups.head.can.heartbeat_ms",
       "unknown key \"heartbeat_ms\"; expected one of feedback, feedforward, heartbeat_period_ms"},
  };
  for (const auto& c : cases) {
    const auto issues = issues_of(small_rig_with(25, kSocketcanHead + c.group_tail));
    ASSERT_EQ(issues.size(), 1u) << c.group_tail << describe(issues);
    EXPECT_EQ(issues[0].line, 25) << issues[0].to_string();
    EXPECT_EQ(issues[0].column, c.column) << issues[0].to_string();
    EXPECT_EQ(issues[0].key_path, c.key_path) << issues[0].to_string();
    EXPECT_NE(issues[0].message.find(c.text), std::string::npos) << issues[0].to_string();
  }
  const auto window = issues_of(
      small_rig_with(23,
                     "    can: {node_id: 2, gear_ratio: 50, encoder_counts_per_rev: 4096, "
                     "following_error_window_deg: -1}"));
  ASSERT_EQ(window.size(), 1u) << describe(window);
  EXPECT_EQ(window[0].key_path, "joints.tilt.can.following_error_window_deg");
}

TEST(BusKeys, InterfaceIsAnInterfaceName) {
  for (const std::string name : {"../etc", "can0:1", "a_name_that_is_too_long"}) {
    const auto issues = issues_of(small_rig_with(34, "  can0: {interface: '" + name + "'}"));
    ASSERT_EQ(issues.size(), 1u) << describe(issues);
    EXPECT_EQ(issues[0].key_path, "can_buses.can0.interface");
    EXPECT_NE(issues[0].message.find("expected a network interface name"), std::string::npos);
  }
  EXPECT_NO_THROW(load_rig_from_string(small_rig_with(34, "  can0: {interface: vcan0}"), "t"));
}

/// Every group of a shipped rig switched to socketcan, as `--set groups.<g>.backend=socketcan`.
std::vector<ConfigOverride> all_socketcan(const std::string& rig_file) {
  std::vector<std::string> texts;
  for (const auto& group : load_rig(test::shipped_rig_path(rig_file)).groups) {
    texts.push_back("groups." + group.name + ".backend=socketcan");
  }
  return sets(texts);
}

TEST(ShippedRigsOnCan, EveryBusStaysWithinTheLimit) {
  for (const std::string rig_file : {"cambio.yaml", "pan_tilt.yaml"}) {
    SCOPED_TRACE(rig_file);
    const RigConfig rig = load_rig(test::shipped_rig_path(rig_file), all_socketcan(rig_file));
    for (const auto& group : rig.groups) EXPECT_EQ(group.backend, "socketcan");
    std::size_t groups_on_buses = 0;
    EXPECT_TRUE(
        check_issues(test::read_text(test::shipped_rig_path(rig_file)), all_socketcan(rig_file))
            .empty());
    for (const auto& bus : rig.can_buses) {
      const CanBusLoad load = load_on(rig, bus.name);
      EXPECT_LE(load.load, kMaxCanBusLoad) << bus.name;
      groups_on_buses += load.groups.size();
    }
    EXPECT_EQ(groups_on_buses, rig.groups.size());
  }
}

TEST(ShippedRigsOnCan, PanTiltRunsAt1kHzOnClassicOneMegabit) {
  const RigConfig rig =
      load_rig(test::shipped_rig_path("pan_tilt.yaml"), all_socketcan("pan_tilt.yaml"));
  ASSERT_EQ(rig.can_buses.size(), 1u);
  EXPECT_FALSE(rig.can_buses[0].fd);
  EXPECT_EQ(rig.can_buses[0].bitrate_bit_s, 1'000'000);
  EXPECT_EQ(rig.groups.at(0).rate_hz, 1000.0);
  EXPECT_DOUBLE_EQ(load_on(rig, "can0").load, 0.5163);
  EXPECT_LE(0.5163, 0.6);
}

TEST(ShippedRigsOnCan, TheRobotsGroupsHaveABusEachAtTheDocumentedLoads) {
  const RigConfig rig =
      load_rig(test::shipped_rig_path("cambio.yaml"), all_socketcan("cambio.yaml"));
  const std::vector<std::pair<std::string, double>> expected = {
      {"can0", 485'250.0}, {"can1", 304'500.0}, {"can2", 304'500.0}};
  for (const auto& [bus, bit_s] : expected) {
    const CanBusLoad load = load_on(rig, bus);
    ASSERT_EQ(load.groups.size(), 1u) << bus;
    EXPECT_DOUBLE_EQ(load.bit_s, bit_s) << bus;
  }
}

TEST(ShippedRigsOnCan, TheRobotsCanSideReachesTheMaster) {
  const canopen::CanRigInfo can_rig =
      canopen::can_rig_from_config(load_rig(test::shipped_rig_path("cambio.yaml")));
  ASSERT_EQ(can_rig.buses.size(), 3u);
  EXPECT_EQ(can_rig.find_group("head")->bus, "can0");
  EXPECT_EQ(can_rig.find_group("right_arm")->bus, "can2");
  const canopen::JointDriveInfo* eye = can_rig.find_drive("left_eye_pan");
  ASSERT_NE(eye, nullptr);
  EXPECT_EQ(eye->node_id, 4);
  EXPECT_EQ(eye->gear_ratio, 50.0);
  EXPECT_EQ(eye->encoder_counts_per_rev, 4096);
  EXPECT_EQ(eye->mode, hal::CommandMode::kPosition);
}

TEST(CanCheck, SocketcanGroupWithoutABus) {
  expect_single_issue(
      check_issues(small_rig_with(25, "  head: {backend: socketcan, joints: [pan, tilt]}")), 25, 9,
      "groups.head.can_bus", "a socketcan group needs can_bus naming one of can_buses: can0");
  expect_single_issue(check_issues(small_rig_with(
                          25, "  head: {backend: socketcan, joints: [pan, tilt], can_bus: can9}")),
                      25, 60, "groups.head.can_bus",
                      "expected one of can_buses (can0), found \"can9\"");
  // A sim group's bus is the virtual rig's: it must exist too.
  expect_single_issue(
      check_issues(small_rig_with(25, "  head: {backend: sim, joints: [pan, tilt], can_bus: c}")),
      25, 54, "groups.head.can_bus", "expected one of can_buses (can0), found \"c\"");
}

TEST(CanCheck, SocketcanJointWithoutCanSettings) {
  auto lines = test::kSmallRigLines;
  lines[24] = "  head: {backend: socketcan, joints: [pan, tilt], can_bus: can0}";
  lines.erase(lines.begin() + 22);  // Line 23: tilt's can map.
  expect_single_issue(check_issues(test::join_lines(lines)), 15, 5, "joints.tilt.can",
                      "missing key (a joint of socketcan group head needs can:");
  // On the sim the joint needs none.
  lines[23] = "  head: {backend: sim, joints: [pan, tilt], can_bus: can0}";
  EXPECT_TRUE(check_issues(test::join_lines(lines)).empty());
}

TEST(CanCheck, DuplicateNodeIdsOnOneBus) {
  expect_single_issue(
      check_issues(small_rig_with(
          23, "    can: {node_id: 1, gear_ratio: 50, encoder_counts_per_rev: 4096}")),
      23, 20, "joints.tilt.can.node_id",
      "expected a node id unique on bus can0, found 1 (already used by pan)");
}

// The rig loader takes any positive gear ratio; before, check-config passed 1e300 and the run
// exited 3 at configure with a 300-digit count. The master's own units check runs in the rig's.
TEST(CanCheck, UnitsWhoseCountsADriveCannotHoldAreRefusedAtTheGearRatio) {
  auto lines = test::kSmallRigLines;
  lines[24] = kSocketcanHead + "}";
  const auto with_pan_can = [&](const std::string& can) {
    auto patched = lines;
    patched[12] = "    can: {" + can + "}";
    return check_issues(test::join_lines(patched));
  };
  expect_single_issue(with_pan_can("node_id: 1, gear_ratio: 1e300, encoder_counts_per_rev: 4096"),
                      13, 35, "joints.pan.can.gear_ratio",
                      "counts, beyond what a drive's INTEGER32");
  // 1e-300 turns every command into count 0; 2^63 - 1 counts per turn overflow too.
  expect_single_issue(with_pan_can("node_id: 1, gear_ratio: 1e-300, encoder_counts_per_rev: 4096"),
                      13, 35, "joints.pan.can.gear_ratio",
                      "counts per joint turn; expected at least 360");
  expect_single_issue(
      with_pan_can("node_id: 1, gear_ratio: 1, encoder_counts_per_rev: 9223372036854775807"), 13,
      35, "joints.pan.can.gear_ratio", "beyond what a drive's INTEGER32");
  // The same units on a sim group are the virtual rig's business, not the master's.
  EXPECT_TRUE(with_pan_can("node_id: 1, gear_ratio: 50, encoder_counts_per_rev: 4096").empty());
}

TEST(CanCheck, TwoSocketcanGroupsCannotShareABus) {
  auto lines = test::kSmallRigLines;
  lines[14] = "    group: tilt_group";
  lines[24] =
      "  head: {backend: socketcan, joints: [pan], can_bus: can0}\n"
      "  tilt_group: {backend: socketcan, joints: [tilt], can_bus: can0}";
  const auto issues = check_issues(test::join_lines(lines));
  ASSERT_EQ(issues.size(), 1u) << describe(issues);
  EXPECT_EQ(issues[0].key_path, "groups.tilt_group.can_bus");
  EXPECT_EQ(issues[0].line, 26);
  EXPECT_NE(issues[0].message.find("already driven by group head"), std::string::npos)
      << issues[0].to_string();
}

TEST(CanCheck, OneGroupsDrivesRunOneCommandMode) {
  auto lines = test::kSmallRigLines;
  lines[12] += "\n    servo: {command: velocity}";
  lines[24] = kSocketcanHead + "}";
  const auto issues = check_issues(test::join_lines(lines));
  ASSERT_EQ(issues.size(), 1u) << describe(issues);
  // tilt has no servo section: the issue is at the joint (its line moved down by pan's servo).
  EXPECT_EQ(issues[0].key_path, "joints.tilt.servo.command");
  EXPECT_EQ(issues[0].line, 16);
}

TEST(CanCheck, TheRobotsHeadAt1kHzExceedsItsBus) {
  auto lines = test::split_lines(test::read_text(test::shipped_rig_path("cambio.yaml")));
  const auto line_of = [&](const std::string& start) {
    const auto it = std::find_if(lines.begin(), lines.end(),
                                 [&](const std::string& line) { return line.starts_with(start); });
    EXPECT_NE(it, lines.end()) << start;
    return static_cast<int>(it - lines.begin()) + 1;
  };
  const int can0_line = line_of("  can0: ");
  ASSERT_EQ(lines.at(static_cast<std::size_t>(can0_line - 1)),
            "  can0: {interface: can0, bitrate_bit_s: 1000000}");
  // The head's five drives at a 1 kHz rate of their own: 5 x (115 + 115) + 55 = 1205 bits per
  // cycle and 5 x 65 bits of heartbeat every 100 ms, 1208250 bit/s: 120.8% of 1 Mbit/s. With
  // 60% of the bus, 600000 - 3250 bit/s of heartbeats leave 1205 x 495.2 Hz.
  const auto issues =
      check_issues(test::patched(lines, line_of("  head: "),
                                 "  head: {backend: socketcan, joints: [neck_pan, neck_tilt, "
                                 "eye_tilt, left_eye_pan, right_eye_pan], can_bus: can0, "
                                 "rate_hz: 1000}"));
  ASSERT_EQ(issues.size(), 1u) << describe(issues);
  EXPECT_EQ(issues[0].line, can0_line);
  EXPECT_EQ(issues[0].column, 42);
  EXPECT_EQ(issues[0].key_path, "can_buses.can0.bitrate_bit_s");
  for (const std::string text :
       {"within 60% (head 5 drives at 1000 Hz: 1208250 bit/s worst case)", "120.8% load",
        "set groups.head.rate_hz to at most 495 Hz", "split the groups over more buses"}) {
    EXPECT_NE(issues[0].message.find(text), std::string::npos) << issues[0].message;
  }
}

}  // namespace
}  // namespace cambio::config
