// Tests of firmware_config/src/rig_loader.cpp: the shipped rigs load with the values they state,
// and every class of bad input is refused with its exact file, line, column and key path.
#include "cambio/config/rig_loader.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <numbers>

#include "cambio/control/joint_frames.hpp"
#include "cambio/hal/joint_state_tap.hpp"
#include "rig_test_support.hpp"

namespace cambio::config {
namespace {

using test::describe;
using test::issues_of;
using test::small_rig;
using test::small_rig_with;

/// Asserts `issues` holds exactly one issue, at `line`:`column` with `key_path`, whose message
/// contains `text`.
void expect_single_issue(const std::vector<ConfigIssue>& issues, int line, int column,
                         const std::string& key_path, const std::string& text) {
  ASSERT_EQ(issues.size(), 1u) << describe(issues);
  const ConfigIssue& issue = issues.front();
  EXPECT_EQ(issue.file, "test.yaml");
  EXPECT_EQ(issue.line, line) << issue.to_string();
  EXPECT_EQ(issue.column, column) << issue.to_string();
  EXPECT_EQ(issue.key_path, key_path) << issue.to_string();
  EXPECT_NE(issue.message.find(text), std::string::npos) << issue.to_string();
}

// ---------------------------------------------------------------------------------------------
// The shipped rigs

TEST(ShippedRigs, CambioLoadsWithItsStatedValues) {
  const RigConfig rig = load_rig(test::shipped_rig_path("cambio.yaml"));
  EXPECT_EQ(rig.name, "cambio");
  ASSERT_EQ(rig.joints.size(), 15u);
  ASSERT_EQ(rig.groups.size(), 3u);
  EXPECT_EQ(rig.groups[0].joints, (std::vector<std::string>{"neck_pan", "neck_tilt", "eye_tilt",
                                                            "left_eye_pan", "right_eye_pan"}));

  // _deg keys arrive in radians: -90 deg is -pi/2, 140 deg is 7 pi / 9.
  const JointConfig* neck_pan = rig.find_joint("neck_pan");
  ASSERT_NE(neck_pan, nullptr);
  EXPECT_DOUBLE_EQ(neck_pan->min_position_rad, -std::numbers::pi / 2);
  EXPECT_DOUBLE_EQ(neck_pan->max_position_rad, std::numbers::pi / 2);
  EXPECT_EQ(neck_pan->max_velocity_rad_s, 2.0);
  EXPECT_EQ(neck_pan->parent, "base");
  EXPECT_EQ(neck_pan->origin.xyz_m, (std::array<double, 3>{0.0, 0.0, 1.2}));
  EXPECT_EQ(neck_pan->axis, (std::array<double, 3>{0.0, 0.0, 1.0}));
  EXPECT_EQ(neck_pan->initial_position_rad, 0.0);
  EXPECT_EQ(neck_pan->servo.encoder_counts_per_rev, 65536);
  ASSERT_TRUE(neck_pan->can.has_value());
  EXPECT_EQ(neck_pan->can->node_id, 1);
  EXPECT_EQ(neck_pan->can->gear_ratio, 100.0);
  EXPECT_DOUBLE_EQ(rig.find_joint("left_elbow")->max_position_rad, 7 * std::numbers::pi / 9);
  EXPECT_DOUBLE_EQ(rig.find_joint("neck_tilt")->max_position_rad, std::numbers::pi / 4);

  const CameraConfig* left = rig.find_camera("left_eye");
  ASSERT_NE(left, nullptr);
  EXPECT_EQ(left->width_px, 640);
  EXPECT_EQ(left->height_px, 480);
  EXPECT_EQ(left->focal_x_px, 554.256);
  EXPECT_EQ(left->focal_y_px, 554.256);
  EXPECT_EQ(left->principal_x_px, 319.5);
  EXPECT_EQ(left->format, PixelFormatConfig::kRgb8);
  EXPECT_DOUBLE_EQ(left->mount.rpy_rad[0], -std::numbers::pi / 2);
  EXPECT_DOUBLE_EQ(left->mount.rpy_rad[2], -std::numbers::pi / 2);

  ASSERT_TRUE(rig.stereo.has_value());
  EXPECT_EQ(rig.stereo->baseline_m, 0.12);
  EXPECT_EQ(rig.touch_sensors.size(), 2u);
  ASSERT_EQ(rig.can_buses.size(), 3u);
  EXPECT_EQ(rig.find_can_bus("can1")->bitrate_bit_s, 1'000'000);
  EXPECT_EQ(rig.find_loop("joint")->rate_hz, 400.0);
  EXPECT_EQ(rig.find_group("head")->rate_hz, 400.0);
  EXPECT_FALSE(rig.find_group("head")->own_rate);
  EXPECT_EQ(rig.find_group("left_arm")->rate_hz, 250.0);
  EXPECT_TRUE(rig.find_group("left_arm")->own_rate);
  EXPECT_EQ(rig.find_loop("joint")->priority, 80);
  EXPECT_EQ(rig.find_loop("camera")->rate_hz, 30.0);
  EXPECT_EQ(rig.sim.physics_rate_hz, 1000.0);
  EXPECT_EQ(rig.sim.render_device, RenderDevice{});  // auto
  EXPECT_FALSE(rig.runtime.lock_memory);
}

TEST(ShippedRigs, PanTiltLoadsAndTakesTheDefaultLoops) {
  const RigConfig rig = load_rig(test::shipped_rig_path("pan_tilt.yaml"));
  EXPECT_EQ(rig.name, "pan_tilt");
  ASSERT_EQ(rig.joints.size(), 2u);
  EXPECT_DOUBLE_EQ(rig.find_joint("pan")->min_position_rad, -17 * std::numbers::pi / 18);
  EXPECT_DOUBLE_EQ(rig.find_joint("tilt")->max_position_rad, std::numbers::pi / 3);
  EXPECT_EQ(rig.cameras.size(), 1u);
  EXPECT_FALSE(rig.stereo.has_value());
  ASSERT_EQ(rig.loops.size(), 4u);
  const std::vector<std::pair<std::string, double>> expected = {
      {"joint", 1000.0}, {"control", 200.0}, {"perception", 60.0}, {"camera", 30.0}};
  for (const auto& [name, rate_hz] : expected) {
    const LoopConfig* loop = rig.find_loop(name);
    ASSERT_NE(loop, nullptr) << name;
    EXPECT_EQ(loop->rate_hz, rate_hz) << name;
    EXPECT_EQ(loop->priority, 0);
    EXPECT_EQ(loop->cpu, -1);
    EXPECT_EQ(loop->overrun, OverrunPolicy::kSkip);
  }
  EXPECT_EQ(rig.sim.physics_rate_hz, 1000.0);
  EXPECT_EQ(rig.sim.render_device.kind, RenderDevice::Kind::kAuto);
}

TEST(SmallRig, LoadsClean) {
  const RigConfig rig = load_rig_from_string(small_rig(), "test.yaml");
  EXPECT_EQ(rig.joints.size(), 2u);
  EXPECT_EQ(rig.find_joint("tilt")->parent, "pan");
  EXPECT_EQ(rig.loops.size(), 4u);
}

// ---------------------------------------------------------------------------------------------
// One test per class of bad input

TEST(BadRig, UnknownKeySuggestsTheIntendedOne) {
  const auto issues = issues_of(small_rig_with(11, "    max_velocty_rad_s: 2.0"));
  ASSERT_EQ(issues.size(), 2u) << describe(issues);
  // Sorted by position: the map (missing key) comes before the misspelt key.
  EXPECT_EQ(issues[0].to_string(),
            "test.yaml:5:5: joints.pan.max_velocity_rad_s: missing key (expected a number > 0)");
  EXPECT_EQ(issues[1].to_string(),
            "test.yaml:11:5: joints.pan.max_velocty_rad_s: unknown key \"max_velocty_rad_s\"; did "
            "you mean \"max_velocity_rad_s\"?");
}

TEST(BadRig, WrongTypeNamesExpectedAndFound) {
  const auto issues = issues_of(small_rig_with(11, "    max_velocity_rad_s: fast"));
  ASSERT_EQ(issues.size(), 1u) << describe(issues);
  EXPECT_EQ(
      issues[0].to_string(),
      "test.yaml:11:25: joints.pan.max_velocity_rad_s: expected a number > 0, found \"fast\"");
}

// Line 32 (principal_point_px) carries the foveation too: its map is then the camera's last key.
std::string foveated(const std::string& map) {
  return small_rig_with(32, "    principal_point_px: [319.5, 239.5]\n    sim_foveation: " + map);
}

TEST(SimFoveation, LoadsWhenTheWindowsTileTheImage) {
  const RigConfig rig =
      load_rig_from_string(foveated("{periphery_downscale: 4, fovea_px: 160}"), "test.yaml");
  const SimFoveationConfig& foveation = rig.cameras.at(0).sim_foveation;
  EXPECT_TRUE(foveation.enabled());
  EXPECT_EQ(foveation.periphery_downscale, 4);
  EXPECT_EQ(foveation.fovea_px, 160);
  EXPECT_FALSE(
      load_rig_from_string(small_rig(), "test.yaml").cameras.at(0).sim_foveation.enabled());
}

TEST(SimFoveation, ADownscaleThatDoesNotDivideTheImageIsRefused) {
  expect_single_issue(issues_of(foveated("{periphery_downscale: 7, fovea_px: 160}")), 33, 42,
                      "cameras.eye.sim_foveation.periphery_downscale",
                      "expected a divisor of the 640x480 image's width and height, found 7");
}

TEST(SimFoveation, AFoveaLargerThanTheImageOrOffTheirParityIsRefused) {
  expect_single_issue(issues_of(foveated("{periphery_downscale: 4, fovea_px: 481}")), 33, 55,
                      "cameras.eye.sim_foveation.fovea_px", "expected at most 480 px");
  expect_single_issue(issues_of(foveated("{periphery_downscale: 4, fovea_px: 161}")), 33, 55,
                      "cameras.eye.sim_foveation.fovea_px", "centred on whole pixels, found 161");
}

TEST(SimFoveation, MissingAndUnknownKeysAreNamed) {
  const auto issues = issues_of(foveated("{periphery_downscale: 4, fovea: 160}"));
  ASSERT_EQ(issues.size(), 2U) << describe(issues);
  EXPECT_NE(describe(issues).find("cameras.eye.sim_foveation.fovea_px: missing key"),
            std::string::npos)
      << describe(issues);
  EXPECT_NE(describe(issues).find("unknown key \"fovea\"; expected one of fovea_px"),
            std::string::npos)
      << describe(issues);
}

TEST(BadRig, WrongTypeListForNumber) {
  expect_single_issue(issues_of(small_rig_with(29, "    width_px: [640]")), 29, 15,
                      "cameras.eye.width_px",
                      "expected an integer in [1, 4096], found a list of 1");
}

TEST(BadRig, MissingKeyIsReportedAtItsMap) {
  auto lines = test::kSmallRigLines;
  lines.erase(lines.begin() + 10);  // Line 11: pan's max_velocity_rad_s.
  expect_single_issue(issues_of(test::join_lines(lines)), 5, 5, "joints.pan.max_velocity_rad_s",
                      "missing key (expected a number > 0)");
}

TEST(BadRig, MissingSectionIsReportedAtTheDocument) {
  auto lines = test::kSmallRigLines;
  lines.erase(lines.begin() + 23, lines.begin() + 25);  // Lines 24-25: groups.
  const auto issues = issues_of(test::join_lines(lines));
  ASSERT_EQ(issues.size(), 3u) << describe(issues);
  EXPECT_EQ(issues[0].to_string(),
            "test.yaml:1:1: groups: missing key (expected a map of joint groups by name)");
  // And each joint is then in no group, at its own map.
  EXPECT_EQ(issues[1].key_path, "joints.pan.group");
  EXPECT_EQ(issues[1].line, 5);
  EXPECT_EQ(issues[2].key_path, "joints.tilt.group");
}

TEST(BadRig, OutOfRangeNodeId) {
  expect_single_issue(
      issues_of(small_rig_with(
          13, "    can: {node_id: 200, gear_ratio: 50, encoder_counts_per_rev: 4096}")),
      13, 20, "joints.pan.can.node_id", "expected an integer in [1, 127], found 200");
  expect_single_issue(
      issues_of(small_rig_with(
          13, "    can: {node_id: 0, gear_ratio: 50, encoder_counts_per_rev: 4096}")),
      13, 20, "joints.pan.can.node_id", "expected an integer in [1, 127], found 0");
}

TEST(BadRig, LowerLimitAboveUpper) {
  expect_single_issue(issues_of(small_rig_with(9, "    min_position_deg: 100")), 9, 23,
                      "joints.pan.min_position_deg",
                      "expected a lower limit below max_position_deg (90 deg), found 100 deg");
}

TEST(BadRig, InitialPositionOutsideLimits) {
  expect_single_issue(issues_of(small_rig_with(
                          12, "    max_acceleration_rad_s2: 20.0\n    initial_position_deg: 120")),
                      13, 27, "joints.pan.initial_position_deg",
                      "expected a position within the limits");
}

TEST(SmallRig, TrackingErrorLimitDefaultsToTwentyDegreesOrTheTravel) {
  const RigConfig rig = load_rig_from_string(
      small_rig_with(12, "    max_acceleration_rad_s2: 20.0\n    max_tracking_error_deg: 5"),
      "test.yaml", {});
  EXPECT_DOUBLE_EQ(rig.find_joint("pan")->max_tracking_error_rad, 5.0 * std::numbers::pi / 180);
  EXPECT_DOUBLE_EQ(rig.find_joint("tilt")->max_tracking_error_rad, kDefaultMaxTrackingError_rad);
  EXPECT_DOUBLE_EQ(kDefaultMaxTrackingError_rad, 20.0 * std::numbers::pi / 180);
  // A joint that travels 10 deg cannot lag by 20: its default is its travel.
  const RigConfig short_travel =
      load_rig_from_string(small_rig_with(10, "    max_position_deg: -80"), "test.yaml", {});
  EXPECT_DOUBLE_EQ(short_travel.find_joint("pan")->max_tracking_error_rad,
                   10.0 * std::numbers::pi / 180);
}

TEST(BadRig, TrackingErrorLimitBeyondTheTravelOrNotPositive) {
  expect_single_issue(issues_of(small_rig_with(12,
                                               "    max_acceleration_rad_s2: 20.0\n"
                                               "    max_tracking_error_deg: 200")),
                      13, 29, "joints.pan.max_tracking_error_deg",
                      "expected at most the joint's travel (180 deg), found 200 deg");
  expect_single_issue(issues_of(small_rig_with(12,
                                               "    max_acceleration_rad_s2: 20.0\n"
                                               "    max_tracking_error_rad: 0")),
                      13, 29, "joints.pan.max_tracking_error_rad", "found 0");
}

TEST(BadRig, RateOfZero) {
  const std::string yaml = small_rig() + "loops:\n  joint: {rate_hz: 0}\n";  // Lines 35-36.
  expect_single_issue(issues_of(yaml), 36, 20, "loops.joint.rate_hz",
                      "expected a number in [0.1, 100000] (a run's cycles are its duration times "
                      "its rates), found 0");
}

TEST(BadRig, CustomLoopNeedsARate) {
  const std::string yaml = small_rig() + "loops:\n  logger: {priority: 10}\n";
  expect_single_issue(issues_of(yaml), 36, 11, "loops.logger.rate_hz", "missing key");
}

TEST(BadRig, GroupNamesAnUnknownJoint) {
  expect_single_issue(issues_of(small_rig_with(
                          25, "  head: {backend: sim, joints: [pan, tilt, roll], can_bus: can0}")),
                      25, 44, "groups.head.joints[2]",
                      "expected a joint (pan, tilt), found \"roll\"");
}

TEST(BadRig, JointInNoGroup) {
  expect_single_issue(
      issues_of(small_rig_with(25, "  head: {backend: sim, joints: [pan], can_bus: can0}")), 15, 5,
      "joints.tilt", "expected the joint in one group's joint list, found it in none");
}

TEST(BadRig, JointInTwoGroups) {
  expect_single_issue(
      issues_of(small_rig_with(25,
                               "  head: {backend: sim, joints: [pan, tilt], can_bus: can0}\n"
                               "  other: {backend: sim, joints: [tilt]}")),
      26, 34, "groups.other.joints[0]", "already in group \"head\"");
}

TEST(BadRig, JointGroupDisagreesWithTheGroupsList) {
  // groups.head lists tilt, but tilt says it belongs to "arm".
  expect_single_issue(issues_of(small_rig_with(15, "    group: arm")), 15, 12, "joints.tilt.group",
                      "expected \"head\" (groups.head.joints lists this joint), found \"arm\"");
}

TEST(BadRig, JointGroupKeyNamesAnotherExistingGroup) {
  // Both groups exist; tilt is listed under head but says left.
  const std::string yaml =
      test::patched(test::split_lines(small_rig_with(15, "    group: left")), 25,
                    "  head: {backend: sim, joints: [pan, tilt], can_bus: can0}\n"
                    "  left: {backend: sim, joints: [pan]}");
  const auto issues = issues_of(yaml);
  ASSERT_EQ(issues.size(), 2u) << describe(issues);
  EXPECT_EQ(issues[0].to_string(),
            "test.yaml:15:12: joints.tilt.group: expected \"head\" (groups.head.joints lists this "
            "joint), found \"left\"");
  EXPECT_EQ(issues[1].key_path, "groups.left.joints[0]");
}

TEST(BadRig, ParentNamesAnUnknownJoint) {
  expect_single_issue(issues_of(small_rig_with(16, "    parent: pann")), 16, 13,
                      "joints.tilt.parent", "found \"pann\"; did you mean \"pan\"?");
}

TEST(BadRig, ParentChainWithACycle) {
  expect_single_issue(issues_of(small_rig_with(6, "    parent: tilt")), 6, 13, "joints.pan.parent",
                      "found a cycle: pan -> tilt -> pan");
}

TEST(BadRig, CameraParentUnknown) {
  expect_single_issue(issues_of(small_rig_with(28, "    parent: nose")), 28, 13,
                      "cameras.eye.parent", "expected \"base\" or a joint (base, pan, tilt)");
}

// The 1-based line of the shipped rig that reads `text` (0 if none), so that the tests below
// follow edits elsewhere in the file.
int line_of(const std::vector<std::string>& lines, const std::string& text) {
  const auto found = std::find(lines.begin(), lines.end(), text);
  return found == lines.end() ? 0 : static_cast<int>(found - lines.begin()) + 1;
}

TEST(BadRig, StereoCameraUnknown) {
  const auto lines = test::split_lines(test::read_text(test::shipped_rig_path("cambio.yaml")));
  const int line = line_of(lines, "  left_camera: left_eye");
  ASSERT_GT(line, 0);
  const auto issues = issues_of(test::patched(lines, line, "  left_camera: left_ey"));
  ASSERT_EQ(issues.size(), 1u) << describe(issues);
  EXPECT_EQ(issues[0].to_string(),
            "test.yaml:" + std::to_string(line) +
                ":16: stereo.left_camera: expected a camera (left_eye, right_eye), found "
                "\"left_ey\"; did you mean \"left_eye\"?");
}

TEST(ShippedRigs, TouchSensorsCarryTheirFingertips) {
  const RigConfig rig = load_rig(test::shipped_rig_path("cambio.yaml"));
  ASSERT_EQ(rig.touch_sensors.size(), 2u);
  EXPECT_EQ(rig.touch_sensors[1].parent, "right_gripper");
  EXPECT_DOUBLE_EQ(rig.touch_sensors[1].fingertip_x_m, 0.082);
  EXPECT_DOUBLE_EQ(rig.touch_sensors[1].fingertip_y_m, 0.008);
}

TEST(BadRig, FingertipsThatAreNoPointOnAFingerAreRefused) {
  const auto lines = test::split_lines(test::read_text(test::shipped_rig_path("cambio.yaml")));
  const std::string shipped =
      "  right_hand: {parent: right_gripper, fingertip_xy_m: [0.082, 0.008]}";
  const int line = line_of(lines, shipped);
  ASSERT_GT(line, 0);
  const std::vector<std::pair<std::string, std::string>> cases{
      {"[0.082, 0.008, 0]", "expected a list of 2 numbers [x, y] in m, found a list of 3"},
      {"[0.005, 0.008]", "expected x in [0.01, 1] m"},
      {"[0.082, 0.3]", "y in [0, 0.2] m"},
      {"[0.082, -0.01]", "expected a number in [0, 1], found -0.01"},
  };
  for (const auto& [value, text] : cases) {
    const auto issues = issues_of(test::patched(
        lines, line, "  right_hand: {parent: right_gripper, fingertip_xy_m: " + value + "}"));
    ASSERT_EQ(issues.size(), 1u) << value << "\n" << describe(issues);
    EXPECT_EQ(issues[0].line, line);
    // The list, or the element at fault.
    EXPECT_EQ(issues[0].key_path.rfind("touch_sensors.right_hand.fingertip_xy_m", 0), 0u)
        << issues[0].to_string();
    EXPECT_NE(issues[0].message.find(text), std::string::npos) << issues[0].to_string();
  }
  // Without the key a touch sensor takes the default hand's fingertips.
  const RigConfig rig = load_rig_from_string(
      test::patched(lines, line, "  right_hand: {parent: right_gripper}"), "test.yaml");
  EXPECT_DOUBLE_EQ(rig.touch_sensors[1].fingertip_x_m, TouchSensorConfig{}.fingertip_x_m);
}

TEST(BadRig, StereoBaselineDisagreesWithTheEyeJoints) {
  const auto lines = test::split_lines(test::read_text(test::shipped_rig_path("cambio.yaml")));
  const int line = line_of(lines, "  baseline_m: 0.12");
  ASSERT_GT(line, 0);
  const auto issues = issues_of(test::patched(lines, line, "  baseline_m: 0.10"));
  ASSERT_EQ(issues.size(), 1u) << describe(issues);
  EXPECT_EQ(issues[0].to_string(),
            "test.yaml:" + std::to_string(line) +
                ":15: stereo.baseline_m: expected 0.12 (the distance in y between the "
                "origins of joints left_eye_pan and right_eye_pan), found 0.1");
  // Within 1e-6 m is agreement.
  EXPECT_NO_THROW(load_rig_from_string(test::patched(lines, line, "  baseline_m: 0.1200005"), "t"));
}

TEST(BadRig, FdDataBitrateWithoutFd) {
  expect_single_issue(
      issues_of(small_rig_with(
          34, "  can0: {interface: can0, bitrate_bit_s: 1000000, data_bitrate_bit_s: 5000000}")),
      34, 71, "can_buses.can0.data_bitrate_bit_s", "set fd: true for CAN FD");
  // With fd it is accepted.
  const RigConfig rig = load_rig_from_string(
      small_rig_with(34,
                     "  can0: {interface: can0, bitrate_bit_s: 1000000, fd: true, "
                     "data_bitrate_bit_s: 5000000}"),
      "test.yaml");
  EXPECT_TRUE(rig.can_buses[0].fd);
  EXPECT_EQ(rig.can_buses[0].data_bitrate_bit_s, 5'000'000);
}

TEST(BadRig, AngleInBothDegreesAndRadians) {
  expect_single_issue(
      issues_of(small_rig_with(9, "    min_position_deg: -90\n    min_position_rad: -1.0")), 10, 5,
      "joints.pan.min_position_rad",
      "expected either min_position_deg or min_position_rad, found both");
}

TEST(BadRig, ZeroAxis) {
  expect_single_issue(issues_of(small_rig_with(8, "    axis: [0, 0, 0]")), 8, 11, "joints.pan.axis",
                      "expected a non-zero axis vector");
}

TEST(SmallRig, AxisIsNormalised) {
  const RigConfig rig = load_rig_from_string(small_rig_with(8, "    axis: [0, 3, 4]"), "t");
  EXPECT_DOUBLE_EQ(rig.joints[0].axis[1], 0.6);
  EXPECT_DOUBLE_EQ(rig.joints[0].axis[2], 0.8);
}

TEST(BadRig, FocalNotPositive) {
  expect_single_issue(issues_of(small_rig_with(31, "    focal_px: 0")), 31, 15,
                      "cameras.eye.focal_px", "expected a number > 0, found 0");
}

TEST(BadRig, FocalGivenTwoWays) {
  expect_single_issue(issues_of(small_rig_with(31, "    focal_px: 500\n    focal_x_px: 500")), 32,
                      17, "cameras.eye.focal_x_px", "found both");
}

TEST(BadRig, PrincipalPointOutsideTheImage) {
  expect_single_issue(issues_of(small_rig_with(32, "    principal_point_px: [700, 239.5]")), 32, 25,
                      "cameras.eye.principal_point_px",
                      "expected a point inside the 640x480 image (x in [-0.5, 639.5], y in [-0.5, "
                      "479.5]), found [700, 239.5]");
}

TEST(BadRig, DuplicateJoint) {
  const auto issues = issues_of(small_rig_with(14, "  pan:"));
  ASSERT_FALSE(issues.empty());
  EXPECT_EQ(issues[0].line, 14);
  EXPECT_EQ(issues[0].column, 3);
  EXPECT_EQ(issues[0].key_path, "joints.pan");
}

TEST(BadRig, EveryProblemIsReportedAtOnce) {
  auto lines = test::kSmallRigLines;
  lines[10] = "    max_velocity_rad_s: fast";  // 11
  lines[19] = "    max_position_degs: 45";     // 20
  lines[30] = "    focal_px: -1";              // 31
  const auto issues = issues_of(test::join_lines(lines));
  // Three bad keys: the wrong type, the unknown key (its intended key then missing) and the
  // out-of-range focal length.
  ASSERT_EQ(issues.size(), 4u) << describe(issues);
  EXPECT_EQ(issues[0].line, 11);
  EXPECT_EQ(issues[1].key_path, "joints.tilt.max_position_deg");
  EXPECT_EQ(issues[1].line, 15);
  EXPECT_EQ(issues[2].key_path, "joints.tilt.max_position_degs");
  EXPECT_EQ(issues[2].line, 20);
  EXPECT_EQ(issues[3].key_path, "cameras.eye.focal_px");
  EXPECT_EQ(issues[3].line, 31);
}

TEST(BadRig, ConfigErrorMessageListsEveryIssue) {
  try {
    load_rig_from_string(small_rig_with(11, "    max_velocity_rad_s: fast\n    bogus: 1"),
                         "test.yaml");
    FAIL() << "expected a ConfigError";
  } catch (const ConfigError& error) {
    const std::string what = error.what();
    EXPECT_NE(what.find("2 configuration problems"), std::string::npos) << what;
    EXPECT_NE(what.find("test.yaml:11:25:"), std::string::npos) << what;
    EXPECT_NE(what.find("test.yaml:12:5:"), std::string::npos) << what;
  }
}

TEST(BadRig, MissingFile) {
  try {
    load_rig("/nonexistent/rig.yaml");
    FAIL() << "expected a ConfigError";
  } catch (const ConfigError& error) {
    ASSERT_EQ(error.issues().size(), 1u);
    EXPECT_EQ(error.issues()[0].file, "/nonexistent/rig.yaml");
  }
}

// ---------------------------------------------------------------------------------------------
// Values that size what the program allocates are bounded, each with its reason.

TEST(RigLimits, ServoDeadTime) {
  // 1e6 s passed and the sim allocated a delay line of dead_time_s x physics_rate_hz commands.
  expect_single_issue(issues_of(small_rig_with(
                          12, "    max_acceleration_rad_s2: 20.0\n    servo: {dead_time_s: 1e6}")),
                      13, 26, "joints.pan.servo.dead_time_s",
                      "expected a number in [0, 1] (a drive's dead time is milliseconds; the sim "
                      "delays commands through dead_time_s x physics_rate_hz entries per joint), "
                      "found 1e6");
}

TEST(RigLimits, CameraSize) {
  expect_single_issue(issues_of(small_rig_with(29, "    width_px: 65535")), 29, 15,
                      "cameras.eye.width_px",
                      "expected an integer in [1, 4096] (the sim renders into an offscreen buffer "
                      "of the largest camera's size and keeps several copies of each frame), "
                      "found 65535");
}

TEST(RigLimits, AllCamerasPixels) {
  // The small rig's camera at the largest size, then `extra` more of it: two pass, three do not.
  const auto with_cameras = [](int extra) {
    auto lines = test::kSmallRigLines;
    lines[28] = "    width_px: 4096";   // Line 29.
    lines[29] = "    height_px: 4096";  // Line 30.
    lines[31].clear();                  // Line 32: the principal point, centred by default.
    for (int i = 0; i < extra; ++i) {
      lines[31] += "  eye" + std::to_string(i) +
                   ": {parent: tilt, width_px: 4096, height_px: 4096, focal_px: 500}\n";
    }
    return test::join_lines(lines);
  };
  EXPECT_NO_THROW(load_rig_from_string(with_cameras(1), "test.yaml"));
  expect_single_issue(issues_of(with_cameras(2)), 33, 9, "cameras.eye1",
                      "expected the cameras to hold at most 33554432 pixels together (two of "
                      "4096 x 4096: the sim renders and keeps every camera's frames), found "
                      "50331648 with this camera");
}

TEST(RigLimits, JointCountIsWhatTheJointLoopHolds) {
  static_assert(kMaxJoints == static_cast<std::size_t>(control::kMaxJoints));
  static_assert(kMaxJoints == hal::JointStateTap::kMaxJoints);
}

TEST(RigLimits, JointCount) {
  // The joint loop's frames hold kMaxJoints; more overflowed them.
  std::string yaml = "rig: {name: many}\njoints:\n";
  std::string names;
  for (std::size_t i = 0; i <= kMaxJoints; ++i) {
    const std::string name = "j" + std::to_string(i);
    yaml += "  " + name +
            ": {group: g, axis: [0, 0, 1], min_position_deg: -1, max_position_deg: 1, "
            "max_velocity_rad_s: 1, max_acceleration_rad_s2: 1}\n";
    names += (names.empty() ? "" : ", ") + name;
  }
  yaml += "groups:\n  g: {backend: sim, joints: [" + names + "]}\n";
  const auto issues = issues_of(yaml);
  ASSERT_EQ(issues.size(), 1u) << describe(issues);
  EXPECT_EQ(issues[0].to_string(),
            "test.yaml:3:3: joints: expected at most 32 joints (the joint loop's frames hold that "
            "many), found 33");
}

TEST(RigLimits, Rates) {
  const std::string loops = small_rig() + "loops:\n  camera: {rate_hz: 1e-300}\n";  // Line 36.
  expect_single_issue(issues_of(loops), 36, 21, "loops.camera.rate_hz",
                      "expected a number in [0.1, 100000]");
  const std::string physics = small_rig() + "sim: {physics_rate_hz: 10}\n";  // Line 35.
  expect_single_issue(issues_of(physics), 35, 24, "sim.physics_rate_hz",
                      "expected a number in [100, 100000] (the encoders' 10 ms velocity window "
                      "needs a step of at most 10 ms; the dead-time lines grow with the rate), "
                      "found 10");
}

TEST(RigLimits, CpuIsNotNarrowedSilently) {
  // 2^32 was read as a 64-bit integer and became CPU 0 as an int.
  const std::string yaml = small_rig() + "loops:\n  joint: {cpu: 4294967296}\n";
  expect_single_issue(issues_of(yaml), 36, 16, "loops.joint.cpu",
                      "expected an integer in [-1, 1023] (-1: any; the kernel's CPU sets end "
                      "there), found 4294967296");
}

TEST(RenderDevice, TakesANameOrAnIndex) {
  EXPECT_EQ(load_rig_from_string(small_rig(), "test.yaml").sim.render_device.kind,
            RenderDevice::Kind::kAuto);
  const std::vector<std::pair<std::string, RenderDevice>> cases = {
      {"auto", {RenderDevice::Kind::kAuto, 0}},
      {"surfaceless", {RenderDevice::Kind::kSurfaceless, 0}},
      {"0", {RenderDevice::Kind::kIndex, 0}},
      {"3", {RenderDevice::Kind::kIndex, 3}}};
  for (const auto& [text, device] : cases) {
    const RigConfig rig =
        load_rig_from_string(small_rig() + "sim: {render_device: " + text + "}\n", "test.yaml");
    EXPECT_EQ(rig.sim.render_device, device) << text;
    EXPECT_EQ(to_string(rig.sim.render_device), text);
  }
  // From the command line as from the file.
  const RigConfig rig = load_rig_from_string(small_rig(), "test.yaml",
                                             {parse_override("sim.render_device=surfaceless")});
  EXPECT_EQ(rig.sim.render_device.kind, RenderDevice::Kind::kSurfaceless);
}

TEST(RenderDevice, RefusesAnythingElseNamingTheAcceptedValues) {
  // The device count is the machine's, not the file's: an index too large for this machine is
  // refused when the sim opens it (tests/sim/egl_context_test.cpp), not here.
  for (const std::string text : {"gpu", "-1", "+1", "1.0", "0x1", "Auto", "99999999999"}) {
    const std::string yaml = small_rig() + "sim: {render_device: " + text + "}\n";  // Line 35.
    expect_single_issue(
        issues_of(yaml), 35, 22, "sim.render_device",
        "expected auto, surfaceless or an EGL device index (0, 1, ...), found \"" + text + "\"");
  }
  const std::string list = small_rig() + "sim: {render_device: [0]}\n";
  expect_single_issue(issues_of(list), 35, 22, "sim.render_device", "found a list of 1");
  const std::string typo = small_rig() + "sim: {render_devices: 0}\n";
  expect_single_issue(issues_of(typo), 35, 7, "sim.render_devices",
                      "did you mean \"render_device\"");
}

}  // namespace
}  // namespace cambio::config
