// `cambio calibrate capture` in the simulator: the head is moved through a pose file and each
// view is saved with the joints' readings, which must be the poses asked (to the sim's servo
// noise and encoder counts); and its refusals: a
// joint the rig lacks, an angle beyond a limit, a folder already holding views, a camera that is
// not the stereo pair's. The console's `capture` line is the same code.
#include <cmath>
#include <filesystem>
#include <fstream>
#include <numbers>
#include <string>

#include <gtest/gtest.h>
#include <yaml-cpp/yaml.h>
#include <opencv2/imgcodecs.hpp>

#include "../apps/run_cambio.hpp"

namespace cambio::testing {
namespace {

constexpr double kDegPerRad = 180.0 / std::numbers::pi;

class CalibrateCapture : public ::testing::Test {
 protected:
  void SetUp() override {
    directory_ = std::filesystem::temp_directory_path() /
                 ("cambio_capture_" + std::to_string(::getpid()) + "_" +
                  ::testing::UnitTest::GetInstance()->current_test_info()->name());
    std::filesystem::create_directories(directory_);
  }
  void TearDown() override { std::filesystem::remove_all(directory_); }
  std::filesystem::path write_poses(const std::string& text) const {
    const std::filesystem::path path = directory_ / "poses.yaml";
    std::ofstream(path) << text;
    return path;
  }
  CommandResult capture(const std::filesystem::path& poses, const std::string& camera,
                        const std::filesystem::path& out) const {
    return run_cambio(
        "calibrate capture firmware_config/experiments/vergence_sphere.yaml --poses '" +
        poses.string() + "' --camera " + camera + " --out '" + out.string() + "'");
  }

  std::filesystem::path directory_;
};

TEST_F(CalibrateCapture, SavesEachPoseViewWithTheReadingsOfThatPose) {
  const double poses_deg[3][4] = {{8, -4, 3, 2}, {-6, 5, -2, -3}, {2, 0, 6, 5}};
  const char* joints[4] = {"neck_pan", "neck_tilt", "eye_tilt", "left_eye_pan"};
  std::string text = "poses:\n";
  for (const auto& pose : poses_deg) {
    text += "  - {";
    for (int j = 0; j < 4; ++j) {
      text += std::string(j ? ", " : "") + joints[j] + ": " + std::to_string(pose[j]);
    }
    text += "}\n";
  }
  const CommandResult result = capture(write_poses(text), "left_eye", directory_ / "views");
  ASSERT_EQ(result.exit_code, 0) << result.output;
  for (int v = 0; v < 3; ++v) {
    const std::string id = "view0" + std::to_string(v + 1);
    const cv::Mat image = cv::imread((directory_ / "views" / (id + ".png")).string());
    EXPECT_EQ(image.cols, 640) << id;
    EXPECT_EQ(image.rows, 480) << id;
    const YAML::Node readings = YAML::LoadFile((directory_ / "views" / (id + ".yaml")).string());
    EXPECT_EQ(readings["camera"].as<std::string>(), "left_eye");
    for (int j = 0; j < 4; ++j) {
      // The servo's position noise (0.0002 rad) and encoder counts, no more: the head got there.
      EXPECT_NEAR(readings["joints_rad"][joints[j]].as<double>() * kDegPerRad, poses_deg[v][j],
                  0.05)
          << id << " " << joints[j];
    }
  }
  // The session's transcript says what it did, one view per pose.
  EXPECT_NE(result.output.find("cambio> capture left_eye"), std::string::npos) << result.output;
  EXPECT_NE(result.output.find("view03.yaml"), std::string::npos) << result.output;
}

TEST_F(CalibrateCapture, RefusesUnknownJointsAnglesBeyondLimitsUsedFoldersAndOtherCameras) {
  CommandResult result = capture(write_poses("poses:\n  - {neck_pan: 5, neck_yaw: 2}\n"),
                                 "left_eye", directory_ / "a");
  EXPECT_EQ(result.exit_code, 2) << result.output;
  EXPECT_NE(result.output.find("pose 1: rig 'cambio' has no joint 'neck_yaw'"), std::string::npos)
      << result.output;
  result = capture(write_poses("poses:\n  - {neck_pan: 500}\n"), "left_eye", directory_ / "b");
  EXPECT_EQ(result.exit_code, 2) << result.output;
  EXPECT_NE(result.output.find("pose 1: neck_pan: expected degrees within its limits"),
            std::string::npos)
      << result.output;
  std::filesystem::create_directories(directory_ / "used");
  std::ofstream(directory_ / "used" / "view01.yaml") << "joints_rad: {}\n";
  result = capture(write_poses("poses:\n  - {neck_pan: 5}\n"), "left_eye", directory_ / "used");
  EXPECT_EQ(result.exit_code, 2) << result.output;
  EXPECT_NE(result.output.find("is not empty"), std::string::npos) << result.output;
  result = capture(write_poses("poses:\n  - {neck_pan: 5}\n"), "nose", directory_ / "c");
  EXPECT_EQ(result.exit_code, 2) << result.output;
  EXPECT_NE(result.output.find("capture takes a camera of the stereo pair (left_eye or right_eye)"),
            std::string::npos)
      << result.output;
}

}  // namespace
}  // namespace cambio::testing
