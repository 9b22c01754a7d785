// `cambio calibrate capture` then `cambio calibrate hand-eye` or `cambio calibrate stereo`, end
// to end in the simulator: a chessboard on a box in front of the robot (the scene's `chessboard`
// texture), the head moved through random poses by the drives' servo model (its noise on), each
// view rendered by MuJoCo and saved with the encoders' readings. What the calibrations write must
// be the rig's, which the sim rendered with: nothing here knows the truth but the rig file.
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <map>
#include <numbers>
#include <random>
#include <string>

#include <gtest/gtest.h>
#include <yaml-cpp/yaml.h>

#include "../apps/run_cambio.hpp"
#include "cambio/config/hardware_description.hpp"
#include "cambio/config/rig_loader.hpp"
#include "cambio/config/shipped_config.hpp"

namespace cambio::testing {
namespace {

constexpr double kDegPerRad = 180.0 / std::numbers::pi;

class SimCalibration : public ::testing::Test {
 protected:
  void SetUp() override {
    directory_ = std::filesystem::temp_directory_path() /
                 ("cambio_sim_calibration_" + std::to_string(::getpid()) + "_" +
                  ::testing::UnitTest::GetInstance()->current_test_info()->name());
    std::filesystem::remove_all(directory_);
    std::filesystem::create_directories(directory_);
  }
  void TearDown() override { std::filesystem::remove_all(directory_); }

  /// A 10 x 7 board of 25 mm squares (9 x 6 inner corners) on a 30 cm square face at `xyz`,
  /// turned by `rpy_deg`; and an experiment on it that holds the head.
  std::filesystem::path write_experiment(const std::string& xyz = "[0.80, 0.03, 1.42]",
                                         const std::string& rpy_deg = "[0, 0, 0]") const {
    std::ofstream(directory_ / "board.scene.yaml")
        << "scene:\n  name: board\nworld:\n  floor: true\nobjects:\n"
           "  - name: board\n    shape: box\n    size_m: [0.01, 0.30, 0.30]\n"
           "    xyz_m: "
        << xyz << "\n    rpy_deg: " << rpy_deg
        << "\n    rgb: [0.95, 0.95, 0.95]\n"
           "    texture: {type: chessboard, squares: [10, 7], feature_size_m: 0.025, "
           "second_rgb: [0.05, 0.05, 0.05]}\n";
    const std::filesystem::path experiment = directory_ / "board.yaml";
    std::ofstream(experiment) << "experiment:\n  name: board\n  rig: " << CAMBIO_SOURCE_DIR
                              << "/firmware_config/rigs/cambio.yaml\n"
                                 "  scene: board.scene.yaml\n  executor: lockstep\n"
                                 "  duration_s: 60\n  task: gaze\n"
                                 "  commands: [{at_s: 0, hold: {verge: false}}]\n";
    return experiment;
  }

  std::filesystem::path directory_;
};

TEST_F(SimCalibration, CaptureThenHandEyeRecoversTheMountTheSimRenderedWith) {
  const std::filesystem::path experiment = write_experiment();
  // Twelve poses turning the camera about its pan and both tilts, the board whole in each.
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> pose_deg(-7.0, 7.0);
  std::ofstream poses(directory_ / "poses.yaml");
  poses << "poses:\n";
  for (int v = 0; v < 12; ++v) {
    poses << "  - {neck_pan: " << pose_deg(rng) << ", neck_tilt: " << pose_deg(rng)
          << ", eye_tilt: " << pose_deg(rng) << ", left_eye_pan: " << pose_deg(rng) << "}\n";
  }
  poses.close();
  CommandResult result =
      run_cambio("calibrate capture '" + experiment.string() + "' --poses '" +
                 (directory_ / "poses.yaml").string() + "' --camera left_eye --out '" +
                 (directory_ / "views").string() + "'");
  ASSERT_EQ(result.exit_code, 0) << result.output;
  result = run_cambio("calibrate hand-eye --views '" + (directory_ / "views").string() +
                      "' --board 9x6 --square-mm 25 --rig cambio --camera left_eye --out '" +
                      (directory_ / "out").string() + "'");
  std::cout << result.output;
  ASSERT_EQ(result.exit_code, 0) << result.output;
  // Every view's board was found: the texture is a board OpenCV reads.
  EXPECT_EQ(result.output.find("refused"), std::string::npos) << result.output;

  const hal::HardwareInfo hardware = config::hardware_description(
      config::load_rig(config::find_shipped_config("rigs/cambio.yaml")));
  Eigen::Isometry3d X_PC_rig = Eigen::Isometry3d::Identity();
  for (const auto& camera : hardware.cameras) {
    if (camera.name == "left_eye") X_PC_rig = camera.X_PC;
  }
  const YAML::Node left = YAML::LoadFile(
      (directory_ / "out" / "camera_calibration.yaml").string())["cameras"]["left_eye"];
  config::Pose mount;
  for (std::size_t i = 0; i < 3; ++i) {
    mount.xyz_m[i] = left["origin_xyz_m"][i].as<double>();
    mount.rpy_rad[i] = left["origin_rpy_deg"][i].as<double>() / kDegPerRad;
  }
  const Eigen::Isometry3d X_PC = config::to_isometry(mount);
  const double offset_mm = (X_PC.translation() - X_PC_rig.translation()).norm() * 1000.0;
  const double angle_deg =
      Eigen::AngleAxisd(X_PC.rotation().transpose() * X_PC_rig.rotation()).angle() * kDegPerRad;
  std::printf("sim hand-eye: mount off the rig's by %.3f mm and %.4f deg\n", offset_mm, angle_deg);
  EXPECT_LT(offset_mm, 1.0);
  EXPECT_LT(angle_deg, 0.1);
}

/// A link's pose in base with every joint at zero, walked over the HAL's joints (parents first).
Eigen::Isometry3d link_at_zero_in_base(const hal::HardwareInfo& hardware, const std::string& link) {
  std::map<std::string, Eigen::Isometry3d> X_B{{"base", Eigen::Isometry3d::Identity()}};
  for (const auto& joint : hardware.joints) X_B[joint.name] = X_B.at(joint.parent) * joint.X_PJ;
  return X_B.at(link);
}

/// The right camera's pose in the left's, every joint at zero, from the rig as loaded.
Eigen::Isometry3d X_LR_at_zero(const config::RigConfig& rig) {
  const hal::HardwareInfo hardware = config::hardware_description(rig);
  Eigen::Isometry3d X_BL = Eigen::Isometry3d::Identity();
  Eigen::Isometry3d X_BR = Eigen::Isometry3d::Identity();
  for (const auto& camera : hardware.cameras) {
    const Eigen::Isometry3d X_BC =
        link_at_zero_in_base(hardware, camera.parent_frame) * camera.X_PC;
    if (camera.name == rig.stereo->left_camera) X_BL = X_BC;
    if (camera.name == rig.stereo->right_camera) X_BR = X_BC;
  }
  return X_BL.inverse() * X_BR;
}

TEST_F(SimCalibration, StereoCaptureThenStereoCalibrationRecoversTheRigsCameras) {
  // The board 0.7 m ahead between the eyes, turned 25 deg about the vertical and tipped 15 deg,
  // seen as the neck alone turns (the eyes at zero, as calibrate stereo asks).
  const std::filesystem::path experiment = write_experiment("[0.70, 0.0, 1.42]", "[0, 15, 25]");
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> pan_deg(-15.0, 15.0);
  std::uniform_real_distribution<double> tilt_deg(-10.0, 10.0);
  std::ofstream poses(directory_ / "poses.yaml");
  poses << "poses:\n";
  for (int v = 0; v < 16; ++v) {
    poses << "  - {neck_pan: " << pan_deg(rng) << ", neck_tilt: " << tilt_deg(rng) << "}\n";
  }
  poses.close();
  CommandResult result =
      run_cambio("calibrate capture '" + experiment.string() + "' --poses '" +
                 (directory_ / "poses.yaml").string() + "' --camera stereo --out '" +
                 (directory_ / "views").string() + "'");
  ASSERT_EQ(result.exit_code, 0) << result.output;
  ASSERT_TRUE(std::filesystem::exists(directory_ / "views" / "left16.png")) << result.output;
  ASSERT_TRUE(std::filesystem::exists(directory_ / "views" / "right16.png")) << result.output;
  ASSERT_TRUE(std::filesystem::exists(directory_ / "views" / "pair16.yaml")) << result.output;
  result = run_cambio("calibrate stereo --images '" + (directory_ / "views").string() +
                      "' --board 9x6 --square-mm 25 --rig cambio --out '" +
                      (directory_ / "out").string() + "'");
  std::cout << result.output;
  ASSERT_EQ(result.exit_code, 0) << result.output;

  const std::string rig_file = std::string(CAMBIO_SOURCE_DIR) + "/firmware_config/rigs/cambio.yaml";
  const config::RigConfig truth = config::load_rig(rig_file);
  const config::RigConfig calibrated = config::load_rig(
      rig_file,
      {{"camera_calibration", (directory_ / "out" / "camera_calibration.yaml").string()}});
  for (const char* name : {"left_eye", "right_eye"}) {
    const config::CameraConfig& want = *truth.find_camera(name);
    const config::CameraConfig& got = *calibrated.find_camera(name);
    std::printf("%s: focal %.3f %.3f px (rig %.3f), principal point %.2f %.2f px (rig %.2f %.2f)\n",
                name, got.focal_x_px, got.focal_y_px, want.focal_x_px, got.principal_x_px,
                got.principal_y_px, want.principal_x_px, want.principal_y_px);
    EXPECT_NEAR(got.focal_x_px / want.focal_x_px, 1.0, 0.005) << name;
    EXPECT_NEAR(got.focal_y_px / want.focal_y_px, 1.0, 0.005) << name;
    EXPECT_NEAR(got.principal_x_px, want.principal_x_px, 1.0) << name;
    EXPECT_NEAR(got.principal_y_px, want.principal_y_px, 1.0) << name;
  }
  const Eigen::Isometry3d want_X_LR = X_LR_at_zero(truth);
  const Eigen::Isometry3d got_X_LR = X_LR_at_zero(calibrated);
  const double baseline_error_mm =
      1000.0 * (got_X_LR.translation().norm() - want_X_LR.translation().norm());
  const double rotation_deg =
      Eigen::AngleAxisd(got_X_LR.rotation().transpose() * want_X_LR.rotation()).angle() *
      kDegPerRad;
  std::printf("sim stereo: baseline %.3f mm off, rotation %.4f deg off\n", baseline_error_mm,
              rotation_deg);
  EXPECT_LT(std::abs(baseline_error_mm), 1.0);
  EXPECT_LT(rotation_deg, 0.1);
}

}  // namespace
}  // namespace cambio::testing
