// Tests of firmware_config/src/experiment_loader.cpp.
#include "cambio/config/experiment_config.hpp"

#include <gtest/gtest.h>

#include <sys/stat.h>

#include <filesystem>
#include <numbers>
#include <string>

#include "file_test_support.hpp"
#include "rig_test_support.hpp"

namespace cambio::config {
namespace {

/// An experiment naming `rig` (line 3, the path at column 8), `extra` appended.
std::string experiment_text(const std::string& rig, const std::string& extra = "") {
  return "experiment:\n"
         "  name: test\n"
         "  rig: " +
         rig +
         "\n"
         "  duration_s: 1\n" +
         extra;
}

/// The issues loading `text` (as file `name`) reports, each as "file:line:col: key: message";
/// a test failure if it loads, or throws anything but a ConfigError.
std::vector<std::string> experiment_issues(const std::string& text,
                                           const std::string& name = "/tmp/experiment.yaml",
                                           const std::vector<ConfigOverride>& overrides = {}) {
  std::vector<std::string> issues;
  try {
    load_experiment_from_string(text, name, overrides);
    ADD_FAILURE() << "expected the experiment to be refused";
  } catch (const ConfigError& error) {
    for (const auto& issue : error.issues()) issues.push_back(issue.to_string());
  }
  return issues;
}

std::string joined(const std::vector<std::string>& issues) {
  std::string text;
  for (const auto& issue : issues) text += issue + "\n";
  return text;
}

// ---------------------------------------------------------------------------------------------
// A file the experiment names that cannot be read is reported at the key that names it, whatever
// the reason (never as a library exception, never as the named file's own problem).

TEST(ExperimentNamedFiles, EachPathErrorIsReportedAtItsKey) {
  test::ScratchFolder folder("cambio_experiment_files_test");
  const std::string long_name = folder.path(std::string(300, 'a') + ".yaml");
  const std::string loop = folder.path("loop_a.yaml");
  std::filesystem::create_symlink(folder.path("loop_b.yaml"), loop);
  std::filesystem::create_symlink(loop, folder.path("loop_b.yaml"));
  const struct {
    std::string rig;
    std::string problem;
  } cases[] = {
      {long_name, "the name is too long"},
      {loop, "too many levels of symbolic links"},
      {"/dev/zero", "it is a character device (such as /dev/zero), expected a regular file"},
      {folder.path(""), "it is a directory, expected a YAML file"},
      {folder.path("missing.yaml"), "it does not exist"},
  };
  for (const auto& c : cases) {
    const auto issues = experiment_issues(experiment_text(c.rig));
    ASSERT_EQ(issues.size(), 1u) << joined(issues);
    EXPECT_TRUE(
        issues[0].starts_with("/tmp/experiment.yaml:3:8: experiment.rig: expected a "
                              "readable rig file, found \""))
        << issues[0];
    EXPECT_NE(issues[0].find(c.problem), std::string::npos) << issues[0];
  }
}

TEST(ExperimentNamedFiles, RelativePathsShowWhereTheyResolved) {
  const auto issues = experiment_issues(
      experiment_text("nothing.yaml", "  scene: ../scenes/none.yaml\n"), "/tmp/experiments/x.yaml");
  ASSERT_EQ(issues.size(), 2u) << joined(issues);
  EXPECT_EQ(issues[0],
            "/tmp/experiments/x.yaml:3:8: experiment.rig: expected a readable rig file, found "
            "\"nothing.yaml\" (resolved to \"/tmp/experiments/nothing.yaml\"): it does not exist");
  EXPECT_EQ(issues[1],
            "/tmp/experiments/x.yaml:5:10: experiment.scene: expected a readable scene file, "
            "found \"../scenes/none.yaml\" (resolved to \"/tmp/scenes/none.yaml\"): it does not "
            "exist");
}

TEST(ExperimentNamedFiles, APermissionProblemIsReportedAtTheKey) {
  test::ScratchFolder folder("cambio_experiment_files_test");
  const std::string rig_text = test::read_text(test::shipped_rig_path("pan_tilt.yaml"));
  const std::string closed_rig = folder.write("closed_rig.yaml", rig_text);
  std::filesystem::permissions(closed_rig, std::filesystem::perms::none);
  std::filesystem::create_directories(folder.path("closed"));
  const std::string in_closed_folder = folder.write("closed/rig.yaml", rig_text);
  std::filesystem::permissions(folder.path("closed"), std::filesystem::perms::none);
  for (const std::string& rig : {closed_rig, in_closed_folder}) {
    const std::string issues = test::run_unprivileged(
        [&] { return joined(experiment_issues(experiment_text(rig), "/tmp/experiment.yaml")); });
    EXPECT_EQ(issues,
              "/tmp/experiment.yaml:3:8: experiment.rig: expected a readable rig file, "
              "found \"" +
                  rig + "\": permission denied\n");
  }
}

// ---------------------------------------------------------------------------------------------
// Size-driving values

TEST(ExperimentLimits, DurationIsBoundedWithItsReason) {
  const auto issues = experiment_issues(
      "experiment:\n  name: t\n  rig: " + test::shipped_rig_path("pan_tilt.yaml") +
      "\n  duration_s: 1e12\n");
  ASSERT_EQ(issues.size(), 1u) << joined(issues);
  EXPECT_EQ(issues[0],
            "/tmp/experiment.yaml:4:15: experiment.duration_s: expected a number in (0, 86400] "
            "(a day; a run's cycles, progress and records grow with its duration), found 1e12");
}

// ---------------------------------------------------------------------------------------------
// ros2

TEST(ExperimentFaultRecovery, HomingAfterARebootIsOffUnlessAskedAndABadValueIsRefusedAtItsKey) {
  const std::string rig = test::shipped_rig_path("pan_tilt.yaml");
  EXPECT_FALSE(load_experiment_from_string(experiment_text(rig), "/tmp/e.yaml")
                   .fault_recovery.home_after_reboot);
  const ExperimentConfig config = load_experiment_from_string(
      experiment_text(rig, "  fault_recovery: {max_recoveries: 2, home_after_reboot: true}\n"),
      "/tmp/e.yaml");
  EXPECT_TRUE(config.fault_recovery.home_after_reboot);
  EXPECT_EQ(config.fault_recovery.max_recoveries, 2);
  const auto issues =
      experiment_issues(experiment_text(rig, "  fault_recovery: {home_after_reboot: sometimes}\n"));
  ASSERT_EQ(issues.size(), 1u) << joined(issues);
  EXPECT_NE(issues[0].find("experiment.fault_recovery.home_after_reboot: expected true or false"),
            std::string::npos)
      << issues[0];
}

TEST(ExperimentRos2, AbsentMeansNoBridgeAndGivenKeysKeepTheOthersDefaults) {
  const std::string rig = test::shipped_rig_path("pan_tilt.yaml");
  EXPECT_FALSE(load_experiment_from_string(experiment_text(rig), "/tmp/e.yaml").ros2);
  const ExperimentConfig config =
      load_experiment_from_string(experiment_text(rig, "  ros2: {domain_id: 7}\n"), "/tmp/e.yaml");
  ASSERT_TRUE(config.ros2);
  EXPECT_EQ(config.ros2->domain_id, 7);
  EXPECT_EQ(config.ros2->joint_states_hz, Ros2Config{}.joint_states_hz);
  EXPECT_TRUE(config.ros2->clock);
  EXPECT_TRUE(config.ros2->tf);
}

TEST(ExperimentRos2, ADomainRtpsCannotNumberAndARateBelowZeroAreRefusedAtTheirKeys) {
  const auto issues = experiment_issues(experiment_text(
      test::shipped_rig_path("pan_tilt.yaml"), "  ros2: {domain_id: 233, joint_states_hz: -1}\n"));
  ASSERT_EQ(issues.size(), 2u) << joined(issues);
  EXPECT_NE(issues[0].find("experiment.ros2.domain_id: expected an integer in [0, 232] (RTPS's "
                           "ports for a higher domain exceed 65535), found 233"),
            std::string::npos)
      << issues[0];
  EXPECT_NE(issues[1].find("experiment.ros2.joint_states_hz: expected a number in [0, 1000]"),
            std::string::npos)
      << issues[1];
}

TEST(ExperimentRos2, CommandsFromRos2AreTheGazeLoopsOnlyWriter) {
  const std::string rig = test::shipped_rig_path("cambio.yaml");
  const auto with_script = experiment_issues(experiment_text(
      rig, "  task: gaze\n  ros2: {commands: true}\n  commands:\n    - {at_s: 0, pursue: {}}\n"));
  ASSERT_EQ(with_script.size(), 1u) << joined(with_script);
  EXPECT_NE(with_script[0].find("experiment.commands: a run with ros2.commands takes its gaze "
                                "commands from ROS 2"),
            std::string::npos)
      << with_script[0];
  const auto holding = experiment_issues(experiment_text(rig, "  ros2: {commands: true}\n"));
  ASSERT_EQ(holding.size(), 1u) << joined(holding);
  EXPECT_NE(holding[0].find("experiment.ros2: commands: true needs task gaze"), std::string::npos)
      << holding[0];
}

// ---------------------------------------------------------------------------------------------
// initial_pose

TEST(ExperimentInitialPose, AnUnknownKeyIsOfferedEveryJoint) {
  const std::string rig = test::shipped_rig_path("pan_tilt.yaml");
  const auto typo =
      experiment_issues(experiment_text(rig, "  initial_pose: {pan_deg: 10, tlit_deg: 5}\n"));
  ASSERT_EQ(typo.size(), 1u) << joined(typo);
  EXPECT_EQ(typo[0],
            "/tmp/experiment.yaml:5:31: experiment.initial_pose.tlit_deg: unknown key "
            "\"tlit_deg\"; did you mean \"tilt_deg\"?");
  // With no close name, every joint's keys are listed (not only those the pose gave).
  const auto unknown = experiment_issues(experiment_text(rig, "  initial_pose: {roll_deg: 5}\n"));
  ASSERT_EQ(unknown.size(), 1u) << joined(unknown);
  EXPECT_EQ(unknown[0],
            "/tmp/experiment.yaml:5:18: experiment.initial_pose.roll_deg: unknown key "
            "\"roll_deg\"; expected one of pan_deg, pan_rad, tilt_deg, tilt_rad");
}

TEST(ExperimentInitialPose, APositionOutsideTheLimitsIsRefusedInItsUnit) {
  const auto issues = experiment_issues(
      experiment_text(test::shipped_rig_path("pan_tilt.yaml"), "  initial_pose: {tilt_deg: 80}\n"));
  ASSERT_EQ(issues.size(), 1u) << joined(issues);
  EXPECT_EQ(issues[0],
            "/tmp/experiment.yaml:5:28: experiment.initial_pose.tilt_deg: expected a number in "
            "[-45, 60] (the joint's limits in the rig), found 80");
}

TEST(ExperimentInitialPose, APositionWithinTheLimitsIsApplied) {
  const ExperimentConfig experiment = load_experiment_from_string(
      experiment_text(test::shipped_rig_path("pan_tilt.yaml"), "  initial_pose: {tilt_deg: 30}\n"),
      "/tmp/experiment.yaml");
  EXPECT_DOUBLE_EQ(experiment.rig.find_joint("tilt")->initial_position_rad,
                   30 * std::numbers::pi / 180);
}

}  // namespace
}  // namespace cambio::config
