// A drive's EDS against the master's view of a rig's CAN group: the shipped EDS fits every CAN
// group of the shipped rigs; vendor-like fixtures give the problems they must, each naming the
// object, the joint and what to change.
#include <gtest/gtest.h>

#include <algorithm>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "cambio/canopen/can_rig_from_config.hpp"
#include "cambio/canopen/eds/eds_group_check.hpp"
#include "cambio/config/hardware_description.hpp"
#include "cambio/config/rig_loader.hpp"

namespace cambio::canopen::eds {
namespace {

const std::string kSource = CAMBIO_SOURCE_DIR;
const std::string kShipped = kSource + "/firmware_config/eds/cambio_virtual_drive.eds";
const std::string kFixtures = kSource + "/tests/drivers/canopen/eds/";

std::string file_text(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::ostringstream text;
  text << in.rdbuf();
  return text.str();
}

/// `text` with its last `from` replaced by `to`.
std::string replace_last(std::string text, const std::string& from, const std::string& to) {
  const std::size_t at = text.rfind(from);
  EXPECT_NE(at, std::string::npos) << from;
  return at == std::string::npos ? text : text.replace(at, from.size(), to);
}

EdsFile parsed(const std::string& text, const std::string& name) {
  EdsReadResult result = parse_eds(text, name);
  for (const EdsIssue& issue : result.issues) ADD_FAILURE() << issue.to_string();
  return std::move(result.eds);
}

CanGroupView group_view(const std::string& rig_name, const std::string& group,
                        const std::vector<std::string>& overrides = {}) {
  std::vector<config::ConfigOverride> parsed_overrides;
  for (const auto& text : overrides) parsed_overrides.push_back(config::parse_override(text));
  const config::RigConfig rig =
      config::load_rig(kSource + "/firmware_config/rigs/" + rig_name + ".yaml", parsed_overrides);
  return can_group_view(config::hardware_description(rig), can_rig_from_config(rig), group,
                        rig.find_loop("joint")->rate_hz);
}

std::string report_text(const EdsGroupReport& report) {
  std::string text;
  for (const EdsProblem& problem : report.problems) text += problem.to_string() + "\n";
  return text;
}

/// The problem about `object` whose text says `what`, or nullptr.
const EdsProblem* find_problem(const EdsGroupReport& report, ObjectAddress object,
                               const std::string& what) {
  for (const EdsProblem& problem : report.problems) {
    if (problem.object == object && problem.problem.find(what) != std::string::npos) {
      return &problem;
    }
  }
  return nullptr;
}

using Joints = std::vector<std::string>;

TEST(EdsGroupCheck, TheShippedEdsFitsEveryCanGroupOfTheShippedRigs) {
  const EdsFile eds = parsed(file_text(kShipped), kShipped);
  int groups = 0;
  for (const auto& [rig, group] :
       std::vector<std::pair<std::string, std::string>>{{"pan_tilt", "pan_tilt"},
                                                        {"cambio", "head"},
                                                        {"cambio", "left_arm"},
                                                        {"cambio", "right_arm"}}) {
    const EdsGroupReport report = check_eds_for_group(eds, group_view(rig, group));
    EXPECT_TRUE(report.fits()) << rig << "/" << group << ":\n" << report_text(report);
    EXPECT_GE(report.objects_checked, 20);
    ++groups;
  }
  // With every optional PDO object mapped (both RPDOs and TPDOs full) and a following window.
  const EdsGroupReport full = check_eds_for_group(
      eds, group_view("pan_tilt", "pan_tilt",
                      {"groups.pan_tilt.can={feedforward: [velocity, effort], feedback: "
                       "[velocity, effort]}",
                       "joints.pan.can.following_error_window_deg=2"}));
  EXPECT_TRUE(full.fits()) << report_text(full);
  EXPECT_EQ(groups, 4);
}

TEST(EdsGroupCheck, ObjectsOutsideTheirLimitsAndPdosTheDriveLacks) {
  const EdsFile eds = parsed(file_text(kFixtures + "kinetra_kx40.eds"), "kinetra_kx40.eds");
  const EdsGroupReport report = check_eds_for_group(eds, group_view("pan_tilt", "pan_tilt"));
  EXPECT_FALSE(report.fits());
  // 3 rad/s x 50 x 4096 / 2 pi = 97785 counts/s, above the KX-40's HighLimit of 80000.
  const EdsProblem* velocity = find_problem(report, {0x607F, 0}, "writes 97785");
  ASSERT_NE(velocity, nullptr) << report_text(report);
  EXPECT_EQ(velocity->joints, Joints{"pan"});
  EXPECT_EQ(velocity->object_name, "Max profile velocity");
  EXPECT_NE(velocity->problem.find("0..80000"), std::string::npos);
  EXPECT_NE(velocity->change.find("joints.pan.max_velocity_rad_s"), std::string::npos);
  EXPECT_GT(velocity->line, 0);
  // One RPDO and one TPDO: the master leaves the PDOs a drive lacks alone, so that fits.
  for (const ObjectAddress object : {ObjectAddress{0x1401, 1}, ObjectAddress{0x1601, 0},
                                     ObjectAddress{0x1801, 1}, ObjectAddress{0x1A01, 0}}) {
    EXPECT_EQ(find_problem(report, object, ""), nullptr) << report_text(report);
  }
  // The shipped pan homes (method 17): the KX-40's EDS has no homing objects.
  for (const ObjectAddress object :
       {ObjectAddress{0x6098, 0}, ObjectAddress{0x6099, 1}, ObjectAddress{0x6099, 2},
        ObjectAddress{0x609A, 0}, ObjectAddress{0x607C, 0}}) {
    const EdsProblem* homing = find_problem(report, object, "not in the EDS");
    ASSERT_NE(homing, nullptr) << report_text(report);
    EXPECT_EQ(homing->joints, Joints{"pan"});
    EXPECT_NE(homing->change.find("joints.pan.can.homing"), std::string::npos) << homing->change;
  }
  // 0x607F for each joint and the pan's five homing objects.
  EXPECT_EQ(report.problems.size(), 7u) << report_text(report);
}

TEST(EdsGroupCheck, APdoLayoutBeyondTheDrivesPdosAndMappingEntries) {
  // TPDO1 can hold one object only (sub 0's HighLimit), and velocity feed-forward needs RPDO2.
  const EdsFile eds = parsed(replace_last(file_text(kFixtures + "kinetra_kx40.eds"),
                                          "DefaultValue = 2\r\nLowLimit = 0\r\nHighLimit = 4",
                                          "DefaultValue = 1\r\nLowLimit = 0\r\nHighLimit = 1"),
                             "kinetra_one_tpdo_entry.eds");
  const EdsGroupReport report = check_eds_for_group(
      eds, group_view("pan_tilt", "pan_tilt", {"groups.pan_tilt.can={feedforward: [velocity]}"}));
  const EdsProblem* rpdos =
      find_problem(report, {0x1601, 0}, "needs RPDO1..RPDO2, the drive has 1");
  ASSERT_NE(rpdos, nullptr) << report_text(report);
  EXPECT_NE(rpdos->change.find("groups.pan_tilt.can.feedforward"), std::string::npos);
  const EdsProblem* entries =
      find_problem(report, {0x1A00, 0}, "maps 2 objects in TPDO1, the drive holds 1");
  ASSERT_NE(entries, nullptr) << report_text(report);
  EXPECT_EQ(entries->object_name, "Number of mapped objects");
}

TEST(EdsGroupCheck, MissingObjectsNoHeartbeatAndNoCyclicMode) {
  const EdsFile eds = parsed(file_text(kFixtures + "drivelabs_dl7.eds"), "drivelabs_dl7.eds");
  // Without the pan's homing: what is missing whatever the joints do.
  const EdsGroupReport report =
      check_eds_for_group(eds, group_view("pan_tilt", "pan_tilt", {"joints.pan.can.homing=none"}));
  const std::string all = report_text(report);
  const EdsProblem* heartbeat = find_problem(report, {0x1017, 0}, "not in the EDS");
  ASSERT_NE(heartbeat, nullptr) << all;
  EXPECT_NE(heartbeat->problem.find("producer heartbeat"), std::string::npos);
  EXPECT_NE(heartbeat->change.find("groups.pan_tilt.can.heartbeat_period_ms"), std::string::npos);
  EXPECT_NE(find_problem(report, {0x60C2, 1}, "not in the EDS"), nullptr) << all;
  EXPECT_NE(find_problem(report, {0x60C2, 2}, "not in the EDS"), nullptr) << all;
  const EdsProblem* limit = find_problem(report, {0x607D, 2}, "[607D] has no sub-index 2");
  ASSERT_NE(limit, nullptr) << all;
  EXPECT_EQ(limit->object_name, "Software position limit");
  const EdsProblem* modes =
      find_problem(report, {0x6502, 0}, "PP (1), PV (3), TQ (4), HM (6), not CSP (8)");
  ASSERT_NE(modes, nullptr) << all;
  EXPECT_EQ(modes->joints, (Joints{"pan", "tilt"}));
  EXPECT_EQ(modes->change, "use a drive that supports CSP (8) or CSV (9)");
  // 0x1017, 0x60C2:01, 0x60C2:02, 0x6502, and 0x607D:02 once per joint (its rig keys differ).
  EXPECT_EQ(report.problems.size(), 6u) << all;
}

TEST(EdsGroupCheck, ADriveWithCsvOnlyIsToldToSwitchTheGroupToVelocity) {
  const EdsFile eds = parsed(
      replace_last(file_text(kShipped), "DefaultValue=0x000001A0", "DefaultValue=0x00000100"),
      "csv_only.eds");
  const EdsGroupReport report = check_eds_for_group(eds, group_view("pan_tilt", "pan_tilt"));
  const EdsProblem* modes = find_problem(report, {0x6502, 0}, "lists CSV (9), not CSP (8)");
  ASSERT_NE(modes, nullptr) << report_text(report);
  EXPECT_NE(modes->change.find("joints.pan.servo.command to velocity"), std::string::npos);
  const EdsGroupReport velocity = check_eds_for_group(
      eds, group_view("pan_tilt", "pan_tilt",
                      {"joints.pan.servo.command=velocity", "joints.tilt.servo.command=velocity"}));
  EXPECT_TRUE(velocity.fits()) << report_text(velocity);
}

TEST(EdsGroupCheck, SizeAccessAndMappingThatDoNotFit) {
  std::string text = file_text(kShipped);
  // The heartbeat time as UNSIGNED32, the target position not mappable, statusword write-only.
  text =
      replace_last(text, "ParameterName=Producer heartbeat time\nObjectType=0x7\nDataType=0x0006",
                   "ParameterName=Producer heartbeat time\nObjectType=0x7\nDataType=0x0007");
  text =
      replace_last(text, "DataType=0x0004\nAccessType=rw\nDefaultValue=0\nPDOMapping=1\n\n[607C]",
                   "DataType=0x0004\nAccessType=rw\nDefaultValue=0\nPDOMapping=0\n\n[607C]");
  text =
      replace_last(text, "ParameterName=Statusword\nObjectType=0x7\nDataType=0x0006\nAccessType=ro",
                   "ParameterName=Statusword\nObjectType=0x7\nDataType=0x0006\nAccessType=wo");
  const EdsGroupReport report =
      check_eds_for_group(parsed(text, "unfit.eds"), group_view("pan_tilt", "pan_tilt"));
  const std::string all = report_text(report);
  EXPECT_NE(find_problem(report, {0x1017, 0}, "UNSIGNED32 (32 bits), the master writes 16 bits"),
            nullptr)
      << all;
  EXPECT_NE(find_problem(report, {0x607A, 0}, "PDOMapping=0; the master maps it in RPDO1"), nullptr)
      << all;
  EXPECT_NE(find_problem(report, {0x6041, 0}, "AccessType wo: the master reads it"), nullptr)
      << all;
  EXPECT_NE(find_problem(report, {0x6041, 0}, "AccessType wo; the master maps it in TPDO1"),
            nullptr)
      << all;
}

TEST(EdsGroupCheck, ANodeIdChecksThatJointAlone) {
  const EdsFile eds = parsed(file_text(kFixtures + "kinetra_kx40.eds"), "kinetra_kx40.eds");
  const EdsGroupReport report = check_eds_for_group(eds, group_view("pan_tilt", "pan_tilt"), 2);
  EXPECT_EQ(report.joints_checked, Joints{"tilt"});
  const EdsProblem* velocity = find_problem(report, {0x607F, 0}, "writes 97785");
  ASSERT_NE(velocity, nullptr) << report_text(report);
  EXPECT_EQ(velocity->joints, Joints{"tilt"});
  EXPECT_TRUE(
      check_eds_for_group(eds, group_view("pan_tilt", "pan_tilt"), 9).joints_checked.empty());
}

TEST(EdsGroupCheck, AnUnknownGroupIsRefused) {
  EXPECT_THROW((void)group_view("pan_tilt", "head"), std::invalid_argument);
}

}  // namespace
}  // namespace cambio::canopen::eds
