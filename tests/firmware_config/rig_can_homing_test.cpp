// joints.<j>.can.homing and joints.<j>.can.virtual_drive (rig_loader.cpp): `none` or CiA 402
// homing's settings, each bad value refused at its line, column and key path.
#include <gtest/gtest.h>

#include <numbers>

#include "cambio/config/rig_loader.hpp"
#include "rig_test_support.hpp"

namespace cambio::config {
namespace {

using test::describe;
using test::issues_of;
using test::small_rig_with;

constexpr const char* kCan = "    can: {node_id: 1, gear_ratio: 50, encoder_counts_per_rev: 4096, ";

std::string with_can(const std::string& more) {
  return small_rig_with(13, kCan + more + "}");
}

const std::string kHoming =
    "homing: {method: 17, switch_speed_rad_s: 1.0, zero_speed_rad_s: 0.05, "
    "acceleration_rad_s2: 10, offset_deg: 5, timeout_s: 4}";

TEST(RigCanHoming, NoneAndAbsentMeanNoHoming) {
  EXPECT_FALSE(
      load_rig_from_string(small_rig_with(13, kCan + std::string("homing: none}")), "test.yaml")
          .find_joint("pan")
          ->can->homing);
  EXPECT_FALSE(load_rig_from_string(test::small_rig(), "test.yaml").find_joint("pan")->can->homing);
}

TEST(RigCanHoming, ReadsEverySettingAndTheVirtualDrivesSwitch) {
  const RigConfig rig = load_rig_from_string(
      with_can(kHoming + ", virtual_drive: {home_switch_deg: -20, index_pulse_rad: 0.1}"),
      "test.yaml");
  const JointCanConfig& can = *rig.find_joint("pan")->can;
  ASSERT_TRUE(can.homing);
  EXPECT_EQ(can.homing->method, 17);
  EXPECT_DOUBLE_EQ(can.homing->switch_speed_rad_s, 1.0);
  EXPECT_DOUBLE_EQ(can.homing->zero_speed_rad_s, 0.05);
  EXPECT_DOUBLE_EQ(can.homing->acceleration_rad_s2, 10.0);
  EXPECT_DOUBLE_EQ(can.homing->offset_rad, 5.0 * std::numbers::pi / 180.0);
  EXPECT_DOUBLE_EQ(can.homing->timeout_s, 4.0);
  EXPECT_DOUBLE_EQ(*can.virtual_home_switch_rad, -20.0 * std::numbers::pi / 180.0);
  EXPECT_DOUBLE_EQ(*can.virtual_index_pulse_rad, 0.1);
}

TEST(RigCanHoming, BadValuesAreNamedWhereTheyAre) {
  // Column of the value inside the flow map on line 13.
  const auto one = [](const std::string& more, const std::string& key, const std::string& text) {
    const auto issues = issues_of(with_can(more));
    ASSERT_EQ(issues.size(), 1u) << describe(issues);
    EXPECT_EQ(issues[0].file, "test.yaml");
    EXPECT_EQ(issues[0].line, 13);
    EXPECT_GT(issues[0].column, 70);
    EXPECT_EQ(issues[0].key_path, key) << issues[0].to_string();
    EXPECT_NE(issues[0].message.find(text), std::string::npos) << issues[0].to_string();
  };
  one("homing: never", "joints.pan.can.homing", "none");
  one("homing: {method: 0, switch_speed_rad_s: 1, zero_speed_rad_s: 0.05, "
      "acceleration_rad_s2: 10, timeout_s: 4}",
      "joints.pan.can.homing.method", "write `homing: none`");
  one("homing: {method: 40, switch_speed_rad_s: 1, zero_speed_rad_s: 0.05, "
      "acceleration_rad_s2: 10, timeout_s: 4}",
      "joints.pan.can.homing.method", "[-128, 37]");
  // The small rig's pan may turn at 2 rad/s.
  one("homing: {method: 17, switch_speed_rad_s: 2.5, zero_speed_rad_s: 0.05, "
      "acceleration_rad_s2: 10, timeout_s: 4}",
      "joints.pan.can.homing.switch_speed_rad_s", "max_velocity_rad_s");
  one("homing: {method: 17, switch_speed_rad_s: 1, zero_speed_rad_s: 0.05, "
      "acceleration_rad_s2: 10, timeout_s: 0}",
      "joints.pan.can.homing.timeout_s", "(0, 3600]");
  one("homing: {method: 17, switch_speed_rad_s: 1, zero_speed_rad_s: 0.05, "
      "acceleration_rad_s2: 10, timeout_s: 4, timeout: 3}",
      "joints.pan.can.homing.timeout", "timeout_s");
  one("homing: {method: 17, switch_speed_rad_s: 1, acceleration_rad_s2: 10, timeout_s: 4}",
      "joints.pan.can.homing.zero_speed_rad_s", "missing key");
  one("virtual_drive: {home_switch: 3}", "joints.pan.can.virtual_drive.home_switch", "unknown key");
}

}  // namespace
}  // namespace cambio::config
