// Tests of the gaze task's experiment keys: firmware_config/src/gaze_task_loader.cpp,
// experiment_evaluation_loader.cpp and their place in experiment_loader.cpp (the scene loaded
// once, `scene.` overrides).
#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <filesystem>
#include <numbers>
#include <string>
#include <vector>

#include "cambio/config/experiment_config.hpp"
#include "file_test_support.hpp"
#include "rig_test_support.hpp"

namespace cambio::config {
namespace {

constexpr double kDeg = std::numbers::pi / 180.0;

/// Three objects: two at rest, and a scripted one whose waypoint path starts away from its pose
/// (the sim puts it on its first waypoint at t = 0, sim/src/object_motion.cpp).
constexpr const char* kSceneText =
    "objects:\n"
    "  - {name: sphere, shape: sphere, radius_m: 0.1, xyz_m: [1.0, 0.14, 1.40]}\n"
    "  - {name: cube, shape: box, size_m: [0.1, 0.1, 0.1], xyz_m: [1.1, -0.22, 1.40]}\n"
    "  - name: ball\n"
    "    shape: sphere\n"
    "    radius_m: 0.05\n"
    "    xyz_m: [0, 0, 0.5]\n"
    "    body: scripted\n"
    "    motion:\n"
    "      type: waypoints\n"
    "      waypoints: [{time_s: 0.5, xyz_m: [1.2, 0.3, 1.3]}, {time_s: 2, xyz_m: [1.2, -0.3, "
    "1.3]}]\n";

class GazeExperiment : public ::testing::Test {
 protected:
  GazeExperiment() : scene_path_(folder_.write("gaze_scene.yaml", kSceneText)) {}

  /// A gaze experiment on the shipped stereo rig, with the scene above unless `scene` is false;
  /// `extra` starts at line 7 (line 6 without a scene).
  std::string text(const std::string& extra, bool scene = true) const {
    return "experiment:\n"   // 1
           "  name: gaze\n"  // 2
           "  rig: " +
           test::shipped_rig_path("cambio.yaml") + "\n" +                // 3
           (scene ? "  scene: " + scene_path_ + "\n" : std::string()) +  // 4
           "  duration_s: 4\n"                                           // 5
           "  task: gaze\n" +                                            // 6
           extra;
  }

  ExperimentConfig load(const std::string& extra, const std::vector<std::string>& sets = {},
                        bool scene = true) const {
    return load_experiment_from_string(text(extra, scene), kFile, overrides(sets));
  }

  /// The issues loading fails with, as "file:line:col: key: message"; a test failure if it loads.
  std::vector<std::string> issues(const std::string& extra,
                                  const std::vector<std::string>& sets = {},
                                  bool scene = true) const {
    std::vector<std::string> found;
    try {
      load(extra, sets, scene);
      ADD_FAILURE() << "expected the experiment to be refused";
    } catch (const ConfigError& error) {
      for (const auto& issue : error.issues()) found.push_back(issue.to_string());
    }
    return found;
  }

  static std::vector<ConfigOverride> overrides(const std::vector<std::string>& sets) {
    std::vector<ConfigOverride> result;
    for (const auto& set : sets) result.push_back(parse_override(set));
    return result;
  }

  static std::string joined(const std::vector<std::string>& lines) {
    std::string all;
    for (const auto& line : lines) all += line + "\n";
    return all;
  }

  static constexpr const char* kFile = "/tmp/gaze.yaml";
  test::ScratchFolder folder_{"cambio_gaze_experiment_test"};
  std::string scene_path_;
};

/// One command that needs nothing of the scene.
constexpr const char* kHoldCommand = "  commands: [{at_s: 0, hold: {}}]\n";

// ---------------------------------------------------------------------------------------------
// What loads

TEST_F(GazeExperiment, EveryKeyIsParsed) {
  const ExperimentConfig config = load(
      "  gaze:\n"
      "    dominant_eye: right\n"
      "    fixation_gain: 2.5\n"
      "    neck_rule_deg: 20\n"
      "    default_depth_m: 1.5\n"
      "    vergence: {enabled: false, gain: 0.25, min_confidence: 0.4, max_step_deg: 2}\n"
      "    saccade: {predictive_vergence: false}\n"
      "    pursuit: {position_gain: 3.0, velocity_gain: 0.5}\n"
      "  commands:\n"
      "    - {at_s: 0.0, fixate: {object: sphere}}\n"
      "    - {at_s: 1.5, saccade: {point_m: [1.1, -0.22, 1.40], verge: false}}\n"
      "    - {at_s: 1.5, pursue: {}}\n"
      "    - {at_s: 3.0, fixate: {pixel: [320, 240], verge: false}}\n"
      "    - {at_s: 3.5, saccade: {angles_deg: [10, -5]}}\n"
      "    - {at_s: 3.75, fixate: {angles_rad: [0.1, 0.2]}}\n"
      "    - {at_s: 4.0, hold: {verge: false}}\n"
      "  evaluation:\n"
      "    target_object: cube\n"
      "    key_frames_s: [0.0, 1.0, 4.0]\n"
      "    settle: {disparity_px: 0.25, gaze_error_deg: 0.2}\n"
      "    pursuit_catch_up_s: 0.75\n"
      "  goals:\n"
      "    settle_time_s: {max: 1.0}\n"
      "    final_disparity_px: {max: 0.5}\n"
      "    target_occluded_s: {min: 0.1}\n");
  EXPECT_EQ(config.task, ControlTask::kGaze);
  const GazeTaskConfig& gaze = config.gaze;
  EXPECT_EQ(gaze.dominant_eye, hal::Eye::kRight);
  EXPECT_EQ(gaze.fixation_gain_per_s, 2.5);
  EXPECT_DOUBLE_EQ(gaze.neck_rule_rad, std::numbers::pi / 9);
  EXPECT_EQ(gaze.default_depth_m, 1.5);
  EXPECT_FALSE(gaze.vergence.enabled);
  EXPECT_EQ(gaze.vergence.gain, 0.25);
  EXPECT_EQ(gaze.vergence.min_confidence, 0.4);
  EXPECT_DOUBLE_EQ(gaze.vergence.max_step_rad, std::numbers::pi / 90);
  EXPECT_FALSE(gaze.saccade.predictive_vergence);
  EXPECT_EQ(gaze.pursuit.position_gain_per_s, 3.0);
  EXPECT_EQ(gaze.pursuit.velocity_gain, 0.5);

  ASSERT_EQ(config.commands.size(), 7u);
  const auto& c = config.commands;
  EXPECT_EQ(c[0].at_s, 0.0);
  EXPECT_EQ(c[0].action, GazeAction::kFixate);
  EXPECT_EQ(c[0].target.kind, GazeTargetKind::kPoint);
  EXPECT_EQ(c[0].target.object, "sphere");
  EXPECT_EQ(c[0].target.point_W_m, (std::array<double, 3>{1.0, 0.14, 1.40}));
  EXPECT_TRUE(c[0].verge);
  EXPECT_EQ(c[1].at_s, 1.5);
  EXPECT_EQ(c[1].action, GazeAction::kSaccade);
  EXPECT_EQ(c[1].target.kind, GazeTargetKind::kPoint);
  EXPECT_EQ(c[1].target.object, "");
  EXPECT_EQ(c[1].target.point_W_m, (std::array<double, 3>{1.1, -0.22, 1.40}));
  EXPECT_FALSE(c[1].verge);
  EXPECT_EQ(c[2].at_s, 1.5);  // Equal times keep file order.
  EXPECT_EQ(c[2].action, GazeAction::kPursue);
  EXPECT_EQ(c[2].target.kind, GazeTargetKind::kNone);
  EXPECT_TRUE(c[2].verge);
  EXPECT_EQ(c[3].action, GazeAction::kFixate);
  EXPECT_EQ(c[3].target.kind, GazeTargetKind::kPixel);
  EXPECT_EQ(c[3].target.pixel_px, (std::array<double, 2>{320, 240}));
  EXPECT_FALSE(c[3].verge);
  EXPECT_EQ(c[4].action, GazeAction::kSaccade);
  EXPECT_EQ(c[4].target.kind, GazeTargetKind::kAngles);
  EXPECT_DOUBLE_EQ(c[4].target.angles_rad[0], std::numbers::pi / 18);
  EXPECT_DOUBLE_EQ(c[4].target.angles_rad[1], -std::numbers::pi / 36);
  EXPECT_EQ(c[5].target.kind, GazeTargetKind::kAngles);
  EXPECT_EQ(c[5].target.angles_rad, (std::array<double, 2>{0.1, 0.2}));
  EXPECT_EQ(c[6].at_s, 4.0);
  EXPECT_EQ(c[6].action, GazeAction::kHold);
  EXPECT_EQ(c[6].target.kind, GazeTargetKind::kNone);
  EXPECT_FALSE(c[6].verge);

  EXPECT_EQ(config.evaluation.target_object, "cube");
  EXPECT_EQ(config.evaluation.key_frames_s, (std::vector<double>{0.0, 1.0, 4.0}));
  EXPECT_EQ(config.evaluation.settle.disparity_px, 0.25);
  EXPECT_DOUBLE_EQ(config.evaluation.settle.gaze_error_rad, 0.2 * kDeg);
  EXPECT_EQ(config.evaluation.pursuit_catch_up_s, 0.75);

  ASSERT_EQ(config.goals.size(), 3u);
  EXPECT_EQ(config.goals[0].metric, "settle_time_s");
  EXPECT_EQ(config.goals[0].bound, GoalBound::kMax);
  EXPECT_EQ(config.goals[0].value, 1.0);
  EXPECT_EQ(config.goals[1].metric, "final_disparity_px");
  EXPECT_EQ(config.goals[1].bound, GoalBound::kMax);
  EXPECT_EQ(config.goals[1].value, 0.5);
  EXPECT_EQ(config.goals[2].metric, "target_occluded_s");
  EXPECT_EQ(config.goals[2].bound, GoalBound::kMin);
  EXPECT_EQ(config.goals[2].value, 0.1);

  // The scene is loaded once, for everyone.
  ASSERT_TRUE(config.scene.has_value());
  EXPECT_EQ(config.scene->name, "gaze_scene");
  EXPECT_EQ(config.scene->objects.size(), 3u);
}

TEST_F(GazeExperiment, KeysLeftOutTakeThePlansDefaults) {
  const ExperimentConfig config = load(kHoldCommand);
  // The values the plan gives (not GazeTaskConfig{}'s, which they check).
  const GazeTaskConfig& gaze = config.gaze;
  EXPECT_EQ(gaze.dominant_eye, hal::Eye::kLeft);
  EXPECT_EQ(gaze.fixation_gain_per_s, 4.0);
  EXPECT_DOUBLE_EQ(gaze.neck_rule_rad, std::numbers::pi / 6);
  EXPECT_EQ(gaze.default_depth_m, 1.0);
  EXPECT_TRUE(gaze.vergence.enabled);
  EXPECT_EQ(gaze.vergence.gain, 0.5);
  EXPECT_EQ(gaze.vergence.min_confidence, 0.3);
  EXPECT_EQ(gaze.vergence.max_step_rad, 0.05);
  EXPECT_TRUE(gaze.saccade.predictive_vergence);
  EXPECT_EQ(gaze.pursuit.position_gain_per_s, 4.0);
  EXPECT_EQ(gaze.pursuit.velocity_gain, 1.0);
  ASSERT_EQ(config.commands.size(), 1u);
  EXPECT_EQ(config.commands[0].action, GazeAction::kHold);
  EXPECT_TRUE(config.commands[0].verge);
  // The issue's goals for the sphere: 0.5 px and 0.1 degrees.
  EXPECT_EQ(config.evaluation.target_object, "");
  EXPECT_TRUE(config.evaluation.key_frames_s.empty());
  EXPECT_EQ(config.evaluation.settle.disparity_px, 0.5);
  EXPECT_DOUBLE_EQ(config.evaluation.settle.gaze_error_rad, 0.1 * kDeg);
  EXPECT_EQ(config.evaluation.pursuit_catch_up_s, 0.5);
  EXPECT_TRUE(config.goals.empty());
}

TEST_F(GazeExperiment, AnObjectIsResolvedToItsCentreWhenTheRunStarts) {
  const ExperimentConfig config = load(
      "  commands:\n"
      "    - {at_s: 0, fixate: {object: cube}}\n"
      "    - {at_s: 1, saccade: {object: ball}}\n");
  EXPECT_EQ(config.commands[0].target.point_W_m, (std::array<double, 3>{1.1, -0.22, 1.40}));
  // Not the pose (0, 0, 0.5): the scripted path's first waypoint, where the sim starts it.
  EXPECT_EQ(config.commands[1].target.object, "ball");
  EXPECT_EQ(config.commands[1].target.point_W_m, (std::array<double, 3>{1.2, 0.3, 1.3}));
}

TEST_F(GazeExperiment, TheHoldTaskStillLoads) {
  const ExperimentConfig hold = load_experiment_from_string(
      "experiment:\n  name: h\n  rig: " + test::shipped_rig_path("cambio.yaml") +
          "\n  duration_s: 1\n",
      kFile);
  EXPECT_EQ(hold.task, ControlTask::kHold);
  EXPECT_TRUE(hold.commands.empty());
  EXPECT_FALSE(hold.scene.has_value());
}

TEST_F(GazeExperiment, AFileOfTheRetiredVergenceTaskIsToldWhereItWent) {
  std::vector<std::string> found;
  try {
    load_experiment_from_string(
        "experiment:\n  name: v\n  rig: " + test::shipped_rig_path("cambio.yaml") +
            "\n  scene: " + scene_path_ +
            "\n  duration_s: 1\n  task: vergence\n"
            "  vergence: {gain: 0.25}\n",
        kFile);
    ADD_FAILURE() << "expected the experiment to be refused";
  } catch (const ConfigError& error) {
    for (const auto& issue : error.issues()) found.push_back(issue.to_string());
  }
  ASSERT_EQ(found.size(), 2u) << joined(found);
  EXPECT_EQ(found[0],
            "/tmp/gaze.yaml:6:9: experiment.task: expected one of hold, gaze, found \"vergence\"");
  EXPECT_EQ(found[1],
            "/tmp/gaze.yaml:7:13: experiment.vergence: task vergence was retired: use task gaze, "
            "with these settings under gaze.vergence (the verging eye is the one "
            "gaze.dominant_eye is not)");
}

TEST_F(GazeExperiment, TheShippedExperimentsCarryTheirScene) {
  const ExperimentConfig config =
      load_experiment(find_shipped_config("experiments/vergence_sphere.yaml"));
  ASSERT_TRUE(config.scene.has_value());
  EXPECT_EQ(config.scene->name, "vergence");
  EXPECT_NE(config.scene->find_object("textured_sphere"), nullptr);
}

// Every shipped gaze experiment loads, and each object target sits at its object's centre.
TEST_F(GazeExperiment, EveryShippedGazeExperimentLoadsWithItsTargets) {
  int gaze_experiments = 0;
  const std::filesystem::path dir =
      std::filesystem::path(find_shipped_config("experiments/vergence_sphere.yaml")).parent_path();
  for (const auto& entry : std::filesystem::directory_iterator(dir)) {
    const ExperimentConfig config = load_experiment(entry.path().string());
    if (config.task != ControlTask::kGaze) continue;
    ++gaze_experiments;
    ASSERT_TRUE(config.scene.has_value()) << entry.path();
    EXPECT_FALSE(config.goals.empty()) << entry.path();
    for (const auto& command : config.commands) {
      if (command.target.object.empty()) continue;
      const auto* object = config.scene->find_object(command.target.object);
      ASSERT_NE(object, nullptr) << entry.path();
      EXPECT_EQ(command.target.point_W_m[0], object->pose.xyz_m[0]) << entry.path();
      EXPECT_EQ(command.target.point_W_m[1], object->pose.xyz_m[1]) << entry.path();
    }
  }
  EXPECT_EQ(gaze_experiments, 9);
}

// ---------------------------------------------------------------------------------------------
// Each problem at its key

TEST_F(GazeExperiment, AnUnknownActionIsOfferedTheActions) {
  const auto found = issues("  commands:\n    - {at_s: 0, fixat: {object: sphere}}\n");
  ASSERT_EQ(found.size(), 2u) << joined(found);
  EXPECT_EQ(found[0],
            "/tmp/gaze.yaml:8:7: experiment.commands[0]: missing key (expected one action: "
            "fixate, saccade, pursue, hold, reach, grasp or release)");
  EXPECT_EQ(found[1],
            "/tmp/gaze.yaml:8:17: experiment.commands[0].fixat: unknown key \"fixat\"; did you "
            "mean \"fixate\"?");
}

TEST_F(GazeExperiment, TwoActionsInOneCommandAreRefused) {
  const auto found = issues("  commands: [{at_s: 0, pursue: {}, hold: {}}]\n");
  ASSERT_EQ(found.size(), 1u) << joined(found);
  EXPECT_EQ(found[0],
            "/tmp/gaze.yaml:7:42: experiment.commands[0].hold: expected one action per "
            "command, found pursue and hold");
}

TEST_F(GazeExperiment, TwoTargetsAreRefusedAtTheSecond) {
  const auto found =
      issues("  commands: [{at_s: 0, fixate: {object: sphere, pixel: [320, 240]}}]\n");
  ASSERT_EQ(found.size(), 1u) << joined(found);
  EXPECT_EQ(found[0],
            "/tmp/gaze.yaml:7:56: experiment.commands[0].fixate.pixel: expected one target, "
            "found object and pixel");
}

TEST_F(GazeExperiment, APointFarBeyondTheRobotIsRefused) {
  // 1e300 is finite; before, the loader took it and the run's gaze loop stored NaN.
  const auto found = issues("  commands: [{at_s: 0, saccade: {point_m: [1e300, 0, 1.4]}}]\n");
  ASSERT_EQ(found.size(), 1u) << joined(found);
  EXPECT_NE(found[0].find("experiment.commands[0].saccade.point_m"), std::string::npos) << found[0];
  EXPECT_NE(found[0].find("within a kilometre of the robot"), std::string::npos) << found[0];
}

TEST_F(GazeExperiment, AnglesOfAQuarterTurnOrMoreAreRefused) {
  // At 90 deg the image plane has no direction for the gaze; beyond, tan turns the gaze back.
  const auto found = issues(
      "  commands:\n"
      "    - {at_s: 0, saccade: {angles_deg: [100, 0]}}\n"
      "    - {at_s: 1, saccade: {angles_deg: [0, -90]}}\n"
      "    - {at_s: 2, saccade: {angles_deg: [89, -30]}}\n");
  ASSERT_EQ(found.size(), 2u) << joined(found);
  EXPECT_NE(found[0].find("experiment.commands[0].saccade.angles_deg"), std::string::npos);
  EXPECT_NE(found[0].find("less than a quarter turn"), std::string::npos) << found[0];
  EXPECT_NE(found[1].find("experiment.commands[1].saccade.angles_deg"), std::string::npos);
}

TEST_F(GazeExperiment, AReachFarBeyondTheRobotIsRefused) {
  const auto found = issues("  commands: [{at_s: 0, reach: [0.5, 1e300, 1.0]}]\n");
  ASSERT_FALSE(found.empty());
  EXPECT_NE(found[0].find("experiment.commands[0].reach"), std::string::npos) << found[0];
  EXPECT_NE(found[0].find("within a kilometre of the robot"), std::string::npos) << found[0];
}

TEST_F(GazeExperiment, FixateAndSaccadeNeedATarget) {
  const auto found = issues(
      "  commands:\n"
      "    - {at_s: 0, fixate: {verge: false}}\n"
      "    - {at_s: 1, saccade: {objct: sphere}}\n");
  ASSERT_EQ(found.size(), 3u) << joined(found);
  EXPECT_EQ(found[0],
            "/tmp/gaze.yaml:8:25: experiment.commands[0].fixate: missing key (expected a "
            "target: one of object, point_m, pixel, angles_deg)");
  EXPECT_EQ(found[1],
            "/tmp/gaze.yaml:9:26: experiment.commands[1].saccade: missing key (expected a "
            "target: one of object, point_m, pixel, angles_deg)");
  EXPECT_EQ(found[2],
            "/tmp/gaze.yaml:9:27: experiment.commands[1].saccade.objct: unknown key \"objct\"; "
            "did you mean \"object\"?");
}

TEST_F(GazeExperiment, PursueAndHoldTakeNoTarget) {
  const auto found = issues(
      "  commands:\n"
      "    - {at_s: 0, pursue: {object: sphere}}\n"
      "    - {at_s: 1, hold: {angles_deg: [1, 2]}}\n");
  ASSERT_EQ(found.size(), 2u) << joined(found);
  EXPECT_EQ(found[0],
            "/tmp/gaze.yaml:8:34: experiment.commands[0].pursue.object: pursue takes no target "
            "(pursuit follows what the dominant eye fixates), found object");
  EXPECT_EQ(found[1],
            "/tmp/gaze.yaml:9:36: experiment.commands[1].hold.angles_deg: hold takes no target "
            "(hold keeps the head where it is), found angles_deg");
}

TEST_F(GazeExperiment, CommandTimesMustBeInOrderAndWithinTheRun) {
  const auto found = issues(
      "  commands:\n"
      "    - {at_s: 1.5, hold: {}}\n"
      "    - {at_s: 1.0, hold: {}}\n"
      "    - {at_s: 4.5, hold: {}}\n"
      "    - {at_s: -1, hold: {}}\n");
  ASSERT_EQ(found.size(), 3u) << joined(found);
  EXPECT_EQ(found[0],
            "/tmp/gaze.yaml:9:14: experiment.commands[1].at_s: expected commands in time order, "
            "found at_s 1 after 1.5");
  EXPECT_EQ(found[1],
            "/tmp/gaze.yaml:10:14: experiment.commands[2].at_s: expected a number in [0, 4] (the "
            "experiment's duration_s), found 4.5");
  EXPECT_EQ(found[2],
            "/tmp/gaze.yaml:11:14: experiment.commands[3].at_s: expected a number in [0, 4] (the "
            "experiment's duration_s), found -1");
}

TEST_F(GazeExperiment, AnUnknownObjectIsOfferedTheScenesObjects) {
  const auto found = issues("  commands: [{at_s: 0, fixate: {object: spere}}]\n");
  ASSERT_EQ(found.size(), 1u) << joined(found);
  EXPECT_EQ(found[0],
            "/tmp/gaze.yaml:7:41: experiment.commands[0].fixate.object: unknown object "
            "\"spere\" (scene \"gaze_scene\" in " +
                scene_path_ + " has sphere, cube, ball); did you mean \"sphere\"?");
  const auto far = issues("  commands: [{at_s: 0, fixate: {object: table}}]\n");
  ASSERT_EQ(far.size(), 1u) << joined(far);
  EXPECT_EQ(far[0],
            "/tmp/gaze.yaml:7:41: experiment.commands[0].fixate.object: unknown object "
            "\"table\" (scene \"gaze_scene\" in " +
                scene_path_ + " has sphere, cube, ball)");
}

TEST_F(GazeExperiment, AnObjectNeedsAScene) {
  const auto found = issues("  commands: [{at_s: 0, fixate: {object: sphere}}]\n", {}, false);
  ASSERT_EQ(found.size(), 1u) << joined(found);
  EXPECT_EQ(found[0],
            "/tmp/gaze.yaml:6:41: experiment.commands[0].fixate.object: expected the name of a "
            "scene object, found \"sphere\", but the experiment names no scene "
            "(experiment.scene)");
}

TEST_F(GazeExperiment, APixelMustLieInTheDominantEyesImage) {
  const auto found = issues("  commands: [{at_s: 0, fixate: {pixel: [640, 10]}}]\n");
  ASSERT_EQ(found.size(), 1u) << joined(found);
  EXPECT_EQ(found[0],
            "/tmp/gaze.yaml:7:40: experiment.commands[0].fixate.pixel: expected a pixel of the "
            "dominant eye's 640 x 480 image (camera \"left_eye\"): u in [0, 639], v in [0, 479], "
            "found [640, 10]");
  const auto three = issues("  commands: [{at_s: 0, fixate: {pixel: [1, 2, 3]}}]\n");
  ASSERT_EQ(three.size(), 1u) << joined(three);
  EXPECT_EQ(three[0],
            "/tmp/gaze.yaml:7:40: experiment.commands[0].fixate.pixel: expected [u, v] in "
            "pixels, found 3 numbers");
}

TEST_F(GazeExperiment, GazeKeysOutOfRangeAreRefusedInTheirUnit) {
  const auto found = issues(
      "  gaze: {neck_rule_deg: 95, fixation_gain: 0, dominant_eye: both,\n"
      "         pursuit: {velocity_gain: 3}, vergence: {max_step_deg: 0}}\n" +
      std::string(kHoldCommand));
  ASSERT_EQ(found.size(), 5u) << joined(found);
  EXPECT_EQ(found[0],
            "/tmp/gaze.yaml:7:25: experiment.gaze.neck_rule_deg: expected a number in (0, 90], "
            "found 95");
  EXPECT_EQ(found[1],
            "/tmp/gaze.yaml:7:44: experiment.gaze.fixation_gain: expected a number > 0, found 0");
  EXPECT_EQ(found[2],
            "/tmp/gaze.yaml:7:61: experiment.gaze.dominant_eye: expected one of left, right, "
            "found \"both\"");
  EXPECT_EQ(found[3],
            "/tmp/gaze.yaml:8:35: experiment.gaze.pursuit.velocity_gain: expected a number in "
            "[0, 2], found 3");
  EXPECT_EQ(found[4],
            "/tmp/gaze.yaml:8:64: experiment.gaze.vergence.max_step_deg: expected a number > 0, "
            "found 0");
}

TEST_F(GazeExperiment, AnUnknownGoalMetricGetsASuggestion) {
  const auto found = issues(std::string(kHoldCommand) +
                            "  goals:\n"
                            "    setle_time_s: {max: 1}\n"
                            "    happiness: {min: 1}\n");
  ASSERT_EQ(found.size(), 2u) << joined(found);
  EXPECT_EQ(found[0],
            "/tmp/gaze.yaml:9:19: experiment.goals.setle_time_s: unknown metric "
            "\"setle_time_s\"; did you mean \"settle_time_s\"?");
  EXPECT_EQ(found[1],
            "/tmp/gaze.yaml:10:16: experiment.goals.happiness: unknown metric \"happiness\"; "
            "expected one of final_disparity_px, true_gaze_error_deg, settle_time_s, "
            "saccade_duration_s, max_vergence_error_during_saccade_deg, reverge_time_s, "
            "pursuit_rms_error_deg, max_believed_vs_true_joint_error_rad, "
            "final_believed_vs_true_fixation_error_m, max_believed_vs_true_fixation_error_m, "
            "final_max_abs_eye_pan_deg, max_verging_gaze_error_visible_deg, target_occluded_s, "
            "objects_visited, all_objects_visited_s, time_to_touch_s, touch_position_error_m, "
            "estimated_target_error_m");
}

TEST_F(GazeExperiment, AGoalIsAMaximumOrAMinimum) {
  const auto found = issues(std::string(kHoldCommand) +
                            "  goals:\n"
                            "    settle_time_s: {max: 1, min: 0.5}\n"
                            "    reverge_time_s: {}\n"
                            "    final_disparity_px: {mx: 1}\n");
  ASSERT_EQ(found.size(), 4u) << joined(found);
  EXPECT_EQ(found[0],
            "/tmp/gaze.yaml:9:34: experiment.goals.settle_time_s.min: expected either max or "
            "min, found both");
  EXPECT_EQ(found[1],
            "/tmp/gaze.yaml:10:21: experiment.goals.reverge_time_s: missing key (expected max "
            "or min: {max: v} or {min: v})");
  EXPECT_EQ(found[2],
            "/tmp/gaze.yaml:11:25: experiment.goals.final_disparity_px: missing key (expected "
            "max or min: {max: v} or {min: v})");
  EXPECT_EQ(found[3],
            "/tmp/gaze.yaml:11:26: experiment.goals.final_disparity_px.mx: unknown key \"mx\"; "
            "did you mean \"max\"?");
}

TEST_F(GazeExperiment, GazeKeysWithAnotherTaskAreRefused) {
  const std::string rig = test::shipped_rig_path("cambio.yaml");
  const std::string text = "experiment:\n  name: h\n  rig: " + rig +
                           "\n  duration_s: 1\n  task: hold\n  gaze: {fixation_gain: 2}\n"
                           "  commands: [{at_s: 0, hold: {}}]\n";
  std::vector<std::string> found;
  try {
    load_experiment_from_string(text, kFile);
    ADD_FAILURE() << "expected the experiment to be refused";
  } catch (const ConfigError& error) {
    for (const auto& issue : error.issues()) found.push_back(issue.to_string());
  }
  ASSERT_EQ(found.size(), 2u) << joined(found);
  EXPECT_EQ(found[0],
            "/tmp/gaze.yaml:6:9: experiment.gaze: only task gaze reads gaze (task is "
            "hold)");
  EXPECT_EQ(found[1],
            "/tmp/gaze.yaml:7:13: experiment.commands: only task gaze reads commands "
            "(task is hold)");
}

TEST_F(GazeExperiment, TheGazeTaskNeedsCommandsAStereoRigAndItsOwnVergenceKeys) {
  const auto none = issues("");
  ASSERT_EQ(none.size(), 1u) << joined(none);
  EXPECT_EQ(none[0],
            "/tmp/gaze.yaml:2:3: experiment.commands: missing key (expected at least one command "
            "for task gaze)");
  const auto empty = issues("  commands: []\n");
  ASSERT_EQ(empty.size(), 1u) << joined(empty);
  EXPECT_EQ(empty[0],
            "/tmp/gaze.yaml:7:13: experiment.commands: expected at least one command for task "
            "gaze, found none");
  const auto old_vergence = issues(std::string(kHoldCommand) + "  vergence: {gain: 0.2}\n");
  ASSERT_EQ(old_vergence.size(), 1u) << joined(old_vergence);
  EXPECT_EQ(old_vergence[0],
            "/tmp/gaze.yaml:8:13: experiment.vergence: task vergence was retired: use task gaze, "
            "with these settings under gaze.vergence (the verging eye is the one "
            "gaze.dominant_eye is not)");

  const std::string pan_tilt = test::shipped_rig_path("pan_tilt.yaml");
  std::vector<std::string> mono;
  try {
    load_experiment_from_string("experiment:\n  name: m\n  rig: " + pan_tilt +
                                    "\n  duration_s: 1\n  task: gaze\n" + kHoldCommand,
                                kFile);
    ADD_FAILURE() << "expected the experiment to be refused";
  } catch (const ConfigError& error) {
    for (const auto& issue : error.issues()) mono.push_back(issue.to_string());
  }
  ASSERT_EQ(mono.size(), 1u) << joined(mono);
  EXPECT_EQ(mono[0],
            "/tmp/gaze.yaml:5:9: experiment.task: expected a rig with a stereo pair for "
            "the gaze task, found none in " +
                pan_tilt);
}

TEST_F(GazeExperiment, EvaluationNamesAreCheckedAgainstTheSceneAndTheRun) {
  const auto found = issues(std::string(kHoldCommand) +
                            "  evaluation:\n"
                            "    target_object: cub\n"
                            "    key_frames_s: [0, 5]\n"
                            "    settle: {gaze_error_deg: 0}\n");
  ASSERT_EQ(found.size(), 3u) << joined(found);
  EXPECT_EQ(found[0],
            "/tmp/gaze.yaml:9:20: experiment.evaluation.target_object: unknown object "
            "\"cub\" (scene \"gaze_scene\" in " +
                scene_path_ + " has sphere, cube, ball); did you mean \"cube\"?");
  EXPECT_EQ(found[1],
            "/tmp/gaze.yaml:10:23: experiment.evaluation.key_frames_s[1]: expected a number in "
            "[0, 4] (the experiment's duration_s), found 5");
  EXPECT_EQ(found[2],
            "/tmp/gaze.yaml:11:30: experiment.evaluation.settle.gaze_error_deg: expected a "
            "number > 0, found 0");
  // Without a scene the name cannot be checked and is kept as given.
  EXPECT_EQ(load(std::string(kHoldCommand) + "  evaluation: {target_object: anything}\n", {}, false)
                .evaluation.target_object,
            "anything");
}

// ---------------------------------------------------------------------------------------------
// `scene.` overrides

TEST_F(GazeExperiment, SceneOverridesMoveObjectsAndTheirTargets) {
  const ExperimentConfig config =
      load("  commands: [{at_s: 0, fixate: {object: sphere}}]\n",
           {"scene.objects.0.xyz_m=[1.5, 0.5, 1.2]", "rig.loops.control.rate_hz=100"});
  EXPECT_EQ(config.commands[0].target.point_W_m, (std::array<double, 3>{1.5, 0.5, 1.2}));
  ASSERT_TRUE(config.scene.has_value());
  EXPECT_EQ(config.scene->find_object("sphere")->pose.xyz_m,
            (std::array<double, 3>{1.5, 0.5, 1.2}));
  EXPECT_EQ(config.rig.find_loop("control")->rate_hz, 100.0);
}

TEST_F(GazeExperiment, ABadSceneOverrideIsReportedAsTheOverride) {
  const auto found = issues(
      kHoldCommand, {"scene.objects.1.size_m=[0.1, -1, 0.1]", "scene.objects.3.xyz_m=[0, 0, 0]"});
  ASSERT_EQ(found.size(), 2u) << joined(found);
  EXPECT_EQ(found[0], "--set: objects.3.xyz_m: cannot set item 3 of objects: the list has 3 items");
  EXPECT_EQ(found[1], "--set: objects[1].size_m[1]: expected a number > 0, found -1");
}

TEST_F(GazeExperiment, ASceneOverrideNeedsAScene) {
  const auto found = issues(kHoldCommand, {"scene.objects.0.xyz_m=[0, 0, 0]"}, false);
  ASSERT_EQ(found.size(), 1u) << joined(found);
  EXPECT_EQ(found[0],
            "--set: scene.objects.0.xyz_m: the experiment names no scene (experiment.scene) to "
            "set it in");
}

// ---------------------------------------------------------------------------------------------
// The arms: `arm:` and the arm entries of `commands:`

TEST_F(GazeExperiment, ArmCommandsAndSettingsAreParsed) {
  const ExperimentConfig config = load(
      "  arm: {gain: 5, max_speed_m_s: 0.5, max_acceleration_m_s2: 4, probe_depth_m: 0.02,\n"
      "        approach_m: 0.1, arrive_tolerance_m: 0.003, posture_gain: 1,\n"
      "        gripper_speed_rad_s: 2}\n"
      "  commands:\n"
      "    - {at_s: 0, saccade: {object: cube}}\n"
      "    - {at_s: 1, reach: fixation}\n"
      "    - {at_s: 2, reach: [0.5, -0.1, 1.0], arm: right}\n"
      "    - {at_s: 3, grasp: left}\n"
      "    - {at_s: 3.5, release: both}\n");
  EXPECT_DOUBLE_EQ(config.arm.gain_per_s, 5.0);
  EXPECT_DOUBLE_EQ(config.arm.max_speed_m_s, 0.5);
  EXPECT_DOUBLE_EQ(config.arm.max_acceleration_m_s2, 4.0);
  EXPECT_DOUBLE_EQ(config.arm.probe_depth_m, 0.02);
  EXPECT_DOUBLE_EQ(config.arm.approach_m, 0.1);
  EXPECT_DOUBLE_EQ(config.arm.arrive_tolerance_m, 0.003);
  EXPECT_DOUBLE_EQ(config.arm.posture_gain_per_s, 1.0);
  EXPECT_DOUBLE_EQ(config.arm.gripper_speed_rad_s, 2.0);
  ASSERT_EQ(config.commands.size(), 5u);
  EXPECT_FALSE(config.commands[0].arm);
  ASSERT_TRUE(config.commands[1].arm);
  EXPECT_EQ(config.commands[1].arm->action, ArmActionConfig::kReach);
  EXPECT_TRUE(config.commands[1].arm->to_fixation);
  EXPECT_EQ(config.commands[1].arm->arm, ArmSideConfig::kNearest);
  ASSERT_TRUE(config.commands[2].arm);
  EXPECT_FALSE(config.commands[2].arm->to_fixation);
  EXPECT_EQ(config.commands[2].arm->arm, ArmSideConfig::kRight);
  EXPECT_EQ(config.commands[2].arm->point_W_m, (std::array<double, 3>{0.5, -0.1, 1.0}));
  ASSERT_TRUE(config.commands[3].arm);
  EXPECT_EQ(config.commands[3].arm->action, ArmActionConfig::kGrasp);
  EXPECT_EQ(config.commands[3].arm->arm, ArmSideConfig::kLeft);
  ASSERT_TRUE(config.commands[4].arm);
  EXPECT_EQ(config.commands[4].arm->action, ArmActionConfig::kRelease);
  EXPECT_EQ(config.commands[4].arm->arm, ArmSideConfig::kNearest);
  EXPECT_DOUBLE_EQ(config.commands[4].at_s, 3.5);
}

TEST_F(GazeExperiment, ArmCommandsAreCheckedWhereTheyAre) {
  const auto found = issues(
      "  commands:\n"
      "    - {at_s: 0, reach: fixate}\n"
      "    - {at_s: 1, reach: [0.5, 1.0]}\n"
      "    - {at_s: 1, grasp: nearest}\n"
      "    - {at_s: 2, release: left, arm: left}\n"
      "    - {at_s: 2, saccade: {object: cube}, reach: fixation}\n"
      "    - {at_s: 3, reech: fixation}\n"
      "    - {at_s: 3, reach: fixation, arm: middle}\n");
  const std::string all = joined(found);
  for (const char* expected : {
           "/tmp/gaze.yaml:8:24: experiment.commands[0].reach: expected one of",
           "/tmp/gaze.yaml:9:24: experiment.commands[1].reach: expected",
           "/tmp/gaze.yaml:10:24: experiment.commands[2].grasp: expected one of",
           "/tmp/gaze.yaml:11:37: experiment.commands[3].arm: expected arm only beside reach",
           "experiment.commands[4].reach: expected one action per command, found saccade and "
           "reach",
           "experiment.commands[5].reech: unknown key \"reech\"; did you mean \"reach\"?",
           "/tmp/gaze.yaml:14:39: experiment.commands[6].arm: expected one of nearest, left, "
           "right, "
           "found \"middle\"",
       }) {
    EXPECT_NE(all.find(expected), std::string::npos) << expected << "\nin\n" << all;
  }
}

TEST_F(GazeExperiment, ArmSettingsAreCheckedWithSuggestions) {
  const auto found = issues("  arm: {gain: -1, probe_depth: 0.02}\n" + std::string(kHoldCommand));
  const std::string all = joined(found);
  for (const char* expected : {
           "/tmp/gaze.yaml:7:15: experiment.arm.gain: expected a number > 0, found -1",
           "experiment.arm.probe_depth: unknown key \"probe_depth\"; did you mean "
           "\"probe_depth_m\"?",
       }) {
    EXPECT_NE(all.find(expected), std::string::npos) << expected << "\nin\n" << all;
  }
}

}  // namespace
}  // namespace cambio::config

// ---------------------------------------------------------------------------------------------
// A behaviour instead of commands

namespace cambio::config {
namespace {

TEST_F(GazeExperiment, ABehaviourIsReadWithItsPluginsResolvedAndItsParamsAsWritten) {
  // A plugin is no config file: larger than a config's 1 MiB is fine (a sanitized build's
  // plugin is).
  const std::string plugin = folder_.write("libscan.so", std::string(3u << 20, '\0'));
  const std::filesystem::path folder = std::filesystem::path(plugin).parent_path();
  const ExperimentConfig config = load_experiment_from_string(
      text("  behaviour:\n"                                           // 7
           "    name: scan\n"                                         // 8
           "    rate_hz: 5\n"                                         // 9
           "    plugins: [libscan.so]\n"                              // 10
           "    params: {dwell_s: 0.25, map: log@1.4, on: true}\n"),  // 11
      (folder / "e.yaml").string());
  ASSERT_TRUE(config.behaviour.has_value());
  const BehaviourConfig& behaviour = *config.behaviour;
  EXPECT_EQ(behaviour.name, "scan");
  EXPECT_EQ(behaviour.rate_hz, 5.0);
  EXPECT_EQ(behaviour.plugins, (std::vector<std::string>{(folder / "libscan.so").string()}));
  ASSERT_EQ(behaviour.params.size(), 3u);
  EXPECT_EQ(behaviour.params[0].key, "dwell_s");
  EXPECT_EQ(behaviour.params[0].text, "0.25");
  EXPECT_EQ(behaviour.params[0].where, (folder / "e.yaml").string() + ":11");
  EXPECT_EQ(behaviour.params[1].text, "log@1.4");
  EXPECT_EQ(behaviour.params[2].text, "true");
  EXPECT_TRUE(config.commands.empty());
}

TEST_F(GazeExperiment, ABehaviourSectionsProblemsAreEachAtTheirKey) {
  const auto found = issues(
      "  behaviour:\n"                     // 7
      "    name: scan\n"                   // 8
      "    rate: 5\n"                      // 9
      "    plugins: [missing.so]\n"        // 10
      "    params: {dwell_s: [1, 2]}\n" +  // 11
      std::string(kHoldCommand));          // 12
  ASSERT_EQ(found.size(), 4u) << joined(found);
  EXPECT_NE(joined(found).find("/tmp/gaze.yaml:10:"), std::string::npos) << joined(found);
  EXPECT_NE(joined(found).find("experiment.behaviour.plugins[0]: expected a readable shared "
                               "library, found \"missing.so\" (resolved to \"/tmp/missing.so\")"),
            std::string::npos)
      << joined(found);
  EXPECT_NE(joined(found).find("experiment.behaviour.params.dwell_s: expected a number, text or "
                               "true/false, found a list"),
            std::string::npos)
      << joined(found);
  EXPECT_NE(joined(found).find("experiment.behaviour.rate"), std::string::npos) << joined(found);
  EXPECT_NE(joined(found).find("give either behaviour or commands, not both"), std::string::npos)
      << joined(found);
}

TEST_F(GazeExperiment, TheShippedAttentionScanNamesTheBuiltInBehaviourAndItsObjects) {
  const ExperimentConfig config =
      load_experiment(find_shipped_config("experiments/attention_scan.yaml"));
  ASSERT_TRUE(config.behaviour.has_value());
  EXPECT_EQ(config.behaviour->name, "attention");
  EXPECT_TRUE(config.behaviour->plugins.empty());
  EXPECT_EQ(config.evaluation.visit_objects.size(), 4u);
}

}  // namespace
}  // namespace cambio::config
