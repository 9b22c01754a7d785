// `cambio console` driven through a pipe, as a user's script would: each action changes what the
// simulator's ground truth and the robot's own stereo estimate say, bad lines never stop the run,
// and a piped script is deterministic.
#include <cmath>
#include <filesystem>
#include <fstream>
#include <regex>
#include <string>

#include <gtest/gtest.h>

#include "run_cambio.hpp"

namespace cambio {
namespace {

namespace fs = std::filesystem;
using cambio::testing::CommandResult;
using cambio::testing::run_cambio;

// The vergence scene's textured sphere (firmware_config/scenes/vergence.yaml).
constexpr double kSphereX = 1.0, kSphereY = 0.14, kSphereZ = 1.40, kSphereRadius = 0.10;

class ConsoleTest : public ::testing::Test {
 protected:
  void SetUp() override {
    directory_ = fs::temp_directory_path() /
                 ("cambio_console_" + std::to_string(::getpid()) + "_" +
                  ::testing::UnitTest::GetInstance()->current_test_info()->name());
    fs::remove_all(directory_);
    fs::create_directories(directory_);
  }
  void TearDown() override { fs::remove_all(directory_); }

  CommandResult console(const std::string& script, const std::string& extra = "",
                        const std::string& experiment = "vergence_sphere") {
    const fs::path path = directory_ / "script.txt";
    std::ofstream(path) << script;
    return run_cambio("console firmware_config/experiments/" + experiment + ".yaml --rtf 0 " +
                      extra + " < '" + path.string() + "'");
  }

  fs::path directory_;
};

// The numbers of the last "believed fixation (stereo): (x, y, z) m" line.
std::vector<double> believed_fixation(const std::string& output) {
  static const std::regex line(
      R"(believed fixation \(stereo\): \(([-0-9.]+), ([-0-9.]+), ([-0-9.]+)\) m)");
  std::vector<double> p;
  for (auto it = std::sregex_iterator(output.begin(), output.end(), line);
       it != std::sregex_iterator(); ++it) {
    p = {std::stod((*it)[1]), std::stod((*it)[2]), std::stod((*it)[3])};
  }
  return p;
}

// The true angle (deg) of a joint in the last status table.
double true_joint_deg(const std::string& output, const std::string& joint) {
  const std::regex row(joint + R"( +[-0-9.]+ deg +([-0-9.]+) deg)");
  double value = NAN;
  for (auto it = std::sregex_iterator(output.begin(), output.end(), row);
       it != std::sregex_iterator(); ++it) {
    value = std::stod((*it)[1]);
  }
  return value;
}

TEST_F(ConsoleTest, ASaccadeToAPointLeavesTheEyesVergedOnItsSurface) {
  const CommandResult r = console(
      "saccade point 1.0 0.14 1.40\n"
      "wait 2.0\n"
      "status\n"
      "quit\n");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const std::vector<double> p = believed_fixation(r.output);
  ASSERT_EQ(p.size(), 3U) << r.output;
  // The robot's own stereo estimate (vergence angles, kinematics) lands on the sphere's near
  // surface: the scene file's geometry is the truth.
  const double from_centre_m = std::hypot(p[0] - kSphereX, p[1] - kSphereY, p[2] - kSphereZ);
  EXPECT_NEAR(from_centre_m, kSphereRadius, 0.03) << r.output;
  EXPECT_NE(r.output.find("gaze: saccade, vergence"), std::string::npos) << r.output;
  EXPECT_EQ(r.output.find("saccade under way"), std::string::npos) << r.output;
}

TEST_F(ConsoleTest, AMoveBeyondALimitIsClampedAndSaysSo) {
  const CommandResult r = console(
      "move neck_tilt 200deg\n"
      "wait 1.5\n"
      "status\n");  // End of input: the console quits.
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const std::regex clamped(
      R"(clamped: neck_tilt: 200.0 deg is beyond its upper limit; clamped to ([-0-9.]+) deg)");
  std::smatch match;
  ASSERT_TRUE(std::regex_search(r.output, match, clamped)) << r.output;
  const double limit_deg = std::stod(match[1]);
  EXPECT_LT(limit_deg, 200.0);
  // The simulator's joint is there (within its servo's tracking).
  EXPECT_NEAR(true_joint_deg(r.output, "neck_tilt"), limit_deg, 0.5) << r.output;
  // What the console says the joint does is what the clamp said: one truth.
  EXPECT_NE(r.output.find("moving neck_tilt to " + match[1].str() + "0 deg"), std::string::npos)
      << r.output;
}

TEST_F(ConsoleTest, AnAngleTooLargeForDegreesIsSaidAsGivenAndTheMoveAsClamped) {
  const CommandResult r = console("move neck_pan 1e308\n");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("neck_pan: 1e+308 rad is beyond its upper limit; clamped to 90.0 deg"),
            std::string::npos)
      << r.output;
  EXPECT_NE(r.output.find("moving neck_pan to 90.00 deg"), std::string::npos) << r.output;
  EXPECT_EQ(r.output.find("inf"), std::string::npos) << r.output;
}

TEST_F(ConsoleTest, BadLinesAreRefusedWithWhatWasExpectedAndTheRunGoesOn) {
  const CommandResult r = console(
      "fly to the moon\n"
      "saccade pixel 5000 10\n"
      "saccade pixel 640 480\n"
      "saccade point 1e300 1e300 1e300\n"
      "help zzz\n"
      "look object unicorn\n"
      "move elbow 10deg\n"
      "wait soon\n"
      "verge off\n"
      "pursue\n"
      "wait 0.5\n"
      "status\n"
      "hold\n"
      "wait 0.2\n"
      "status\n");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("error: unknown command \"fly\""), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("refused: pixel (5000, 10) is outside the dominant eye's 640x480 image"),
            std::string::npos)
      << r.output;
  EXPECT_NE(r.output.find("refused: no scene object \"unicorn\""), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("refused: no joint \"elbow\""), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("wait: expected a number of seconds, found \"soon\""), std::string::npos)
      << r.output;
  EXPECT_NE(r.output.find("gaze: pursue"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("gaze: hold"), std::string::npos) << r.output;
  // The experiment loader's bounds, refused at the line, before anything reaches the gaze loop.
  EXPECT_NE(r.output.find("refused: pixel (640, 480) is outside"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("refused: the point (1e+300, 1e+300, 1e+300) m is not one the eyes "
                          "can fixate"),
            std::string::npos)
      << r.output;
  EXPECT_EQ(r.output.find("refused by the gaze loop"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("error: help: expected a command to describe, found \"zzz\""),
            std::string::npos)
      << r.output;
  EXPECT_NE(r.output.find("(8 lines refused)"), std::string::npos) << r.output;
  // Two waits, and one control cycle after each of the three commands sent.
  EXPECT_NE(r.output.find("ran 0.715 s"), std::string::npos) << r.output;
}

TEST_F(ConsoleTest, APipedScriptIsDeterministic) {
  const std::string script =
      "look object textured_sphere\n"
      "wait 0.8\n"
      "status\n"
      "ssm\n";
  const CommandResult first = console(script);
  const CommandResult second = console(script);
  ASSERT_EQ(first.exit_code, 0) << first.output;
  // Everything but wall-clock figures (the SSM's time, the loop table) is the same.
  const auto up_to_table = [](const std::string& text) {
    return std::regex_replace(text.substr(0, text.find("loop ")), std::regex("[0-9]+ us"), "");
  };
  EXPECT_EQ(up_to_table(first.output), up_to_table(second.output));
  EXPECT_NE(first.output.find("ssm frame"), std::string::npos) << first.output;
}

TEST_F(ConsoleTest, SsmSaveWritesEveryMapOfBothEyesAsPng) {
  const fs::path maps = directory_ / "maps";
  const CommandResult r = console("wait 0.3\nssm save " + maps.string() + "\n");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  std::size_t pngs = 0;
  for (const auto& entry : fs::directory_iterator(maps)) pngs += entry.path().extension() == ".png";
  // ssm.yaml: 4 levels, 25 maps per level, both eyes.
  EXPECT_EQ(pngs, 2U * 4U * 25U) << r.output;
  EXPECT_TRUE(fs::exists(maps / "left_L0_intensity.png"));
}

TEST_F(ConsoleTest, OnTheRealtimeExecutorTheLoopsRunOnTheirThreadsAndWaitSleeps) {
  const CommandResult r = console(
      "saccade point 1.0 0.14 1.40\n"
      "wait 2.0\n"  // Wall seconds: room for a slow (sanitized, shared) machine.
      "status\n"
      "quit\n",
      "--set experiment.executor=realtime");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("realtime executor"), std::string::npos) << r.output;
  const std::vector<double> p = believed_fixation(r.output);
  ASSERT_EQ(p.size(), 3U) << r.output;
  EXPECT_NEAR(std::hypot(p[0] - kSphereX, p[1] - kSphereY, p[2] - kSphereZ), kSphereRadius, 0.03)
      << r.output;
}

// An arm's line of the last status: "right arm: touching, gripper closed at (x, y, z) m...".
std::string arm_line(const std::string& output, const std::string& side) {
  const std::regex line(side + R"( arm: [^\n]*)");
  std::string last;
  for (auto it = std::sregex_iterator(output.begin(), output.end(), line);
       it != std::sregex_iterator(); ++it) {
    last = it->str();
  }
  return last;
}

TEST_F(ConsoleTest, TheNearerArmReachesWhatTheHeadFixatesTouchesItAndGrasps) {
  // reach_touch's cube (scenes/reach_touch.yaml) is nearer the right shoulder.
  const CommandResult r = console(
      "saccade object cube\n"
      "wait 1.2\n"
      "reach\n"
      "wait 2.5\n"
      "status\n"
      "release right\n"
      "wait 0.5\n"
      "status\n"
      "move left_elbow 30deg\n"
      "reach point 2 0 1 left\n"
      "wait 1.5\n"
      "status\n",
      "", "reach_touch");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("reaching what the head fixates"), std::string::npos) << r.output;
  const std::size_t first_status = r.output.find("cambio> release right");
  ASSERT_NE(first_status, std::string::npos) << r.output;
  const std::string after_reach = r.output.substr(0, first_status);
  EXPECT_NE(arm_line(after_reach, "right").find("right arm: touching, gripper closed"),
            std::string::npos)
      << r.output;
  const std::string after_release = r.output.substr(0, r.output.find("cambio> move left_elbow"));
  EXPECT_NE(arm_line(after_release, "right").find("gripper open"), std::string::npos) << r.output;
  // The left arm's joint moved (true angle from the simulator); its reach is out of range and
  // the console says why.
  EXPECT_NEAR(true_joint_deg(r.output, "left_elbow"), 30.0, 0.5) << r.output;
  EXPECT_NE(r.output.find("refused by the arms: out of reach: the target is"), std::string::npos)
      << r.output;
}

TEST_F(ConsoleTest, ARefusalByTheLoopsFollowsItsLineEvenTheLastOne) {
  // The arm loop checks reach; the console's line only sends. Before, its refusal was printed
  // after the next line was read, and never for the last line.
  const CommandResult r = console("reach point 2 0 1 left\n", "", "reach_touch");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("refused by the arms: out of reach"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("1 lines refused"), std::string::npos) << r.output;
}

// `home JOINT` reaches the joint's group: the sim's joints read absolute positions, so the group
// refuses, and the console says so after the cycle; `home` alone asks every joint that lost its
// reference (none here) and is no refusal; a name that is no joint is refused at the line.
TEST_F(ConsoleTest, HomingAJointWhoseDriveDoesNotHomeIsRefusedByItsGroup) {
  const CommandResult r = console(
      "home neck_pan\n"
      "home\n"
      "home elbow\n"
      "quit\n");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("homing neck_pan\nrefused: joint \"neck_pan\" does not home"),
            std::string::npos)
      << r.output;
  EXPECT_NE(r.output.find("homing every joint that lost its reference"), std::string::npos)
      << r.output;
  EXPECT_NE(r.output.find("refused: \"elbow\" is not a joint of the rig"), std::string::npos)
      << r.output;
  EXPECT_NE(r.output.find("(2 lines refused)"), std::string::npos) << r.output;
}

TEST_F(ConsoleTest, AnExperimentWithoutTheGazeTaskIsRefusedBeforeAnythingRuns) {
  const CommandResult r = console("status\n", "", "pan_tilt_hold");
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_NE(r.output.find("the console drives the gaze task"), std::string::npos) << r.output;
  EXPECT_EQ(r.output.find("cambio> "), std::string::npos) << r.output;
}

}  // namespace
}  // namespace cambio
