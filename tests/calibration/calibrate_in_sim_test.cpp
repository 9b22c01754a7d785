// `cambio calibrate capture` then `cambio calibrate hand-eye` or `cambio calibrate stereo`, end
// to end in the simulator: a chessboard on a box in front of the robot (the scene's `chessboard`
// texture), the head moved through random poses by the drives' servo model (its noise on), each
// view rendered by MuJoCo and saved with the encoders' readings. What the calibrations write must
// be the rig's, which the sim rendered with: nothing here knows the truth but the rig file.
#include <array>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <map>
#include <numbers>
#include <random>
#include <sstream>
#include <string>

#include <gtest/gtest.h>
#include <yaml-cpp/yaml.h>

#include "../apps/run_cambio.hpp"
#include "cambio/config/hardware_description.hpp"
#include "cambio/config/rig_loader.hpp"
#include "cambio/config/shipped_config.hpp"
#include "cambio/hal/lens_model.hpp"

namespace cambio::testing {
namespace {

constexpr double kDegPerRad = 180.0 / std::numbers::pi;

class SimCalibration : public ::testing::Test {
 public:
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
  std::filesystem::path write_experiment(
      const std::string& xyz = "[0.80, 0.03, 1.42]", const std::string& rpy_deg = "[0, 0, 0]",
      const std::string& rig = std::string(CAMBIO_SOURCE_DIR) +
                               "/firmware_config/rigs/cambio.yaml") const {
    std::ofstream(directory_ / "board.scene.yaml")
        << "scene:\n  name: board\nworld:\n  floor: true\nobjects:\n"
           "  - name: board\n    shape: box\n    size_m: [0.01, 0.30, 0.30]\n"
           "    xyz_m: "
        << xyz << "\n    rpy_deg: " << rpy_deg
        << "\n    rgb: [0.95, 0.95, 0.95]\n"
           "    texture: {type: chessboard, squares: [10, 7], feature_size_m: 0.025, "
           "second_rgb: [0.05, 0.05, 0.05]}\n";
    const std::filesystem::path experiment = directory_ / "board.yaml";
    std::ofstream(experiment) << "experiment:\n  name: board\n  rig: " << rig
                              << "\n"
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

/// The largest distance (px) between where two lens models (each with `truth`'s intrinsics, so
/// that a focal length or principal point error does not count twice) put the ideal pixels within
/// `radius_px` of the image centre.
double largest_lens_difference_px(const config::CameraConfig& truth,
                                  const config::CameraConfig& got, double radius_px) {
  const hal::CameraIntrinsics k{truth.width_px,   truth.height_px,      truth.focal_x_px,
                                truth.focal_y_px, truth.principal_x_px, truth.principal_y_px};
  double largest = 0.0;
  for (int y = 0; y < truth.height_px; y += 8) {
    for (int x = 0; x < truth.width_px; x += 8) {
      if (std::hypot(x - k.principal_x_px, y - k.principal_y_px) > radius_px) continue;
      double u_truth = 0.0;
      double v_truth = 0.0;
      double u_got = 0.0;
      double v_got = 0.0;
      hal::distort_px(k, truth.distortion, x, y, u_truth, v_truth);
      hal::distort_px(k, got.distortion, x, y, u_got, v_got);
      largest = std::max(largest, std::hypot(u_got - u_truth, v_got - v_truth));
    }
  }
  return largest;
}

/// Captures `views` stereo views of the board with the neck alone turning up to `pan_deg` and
/// `tilt_deg` either way (the eyes at zero, as calibrate stereo asks) on `rig_file`, calibrates,
/// and checks what it wrote against the rig.
void capture_and_calibrate_stereo(SimCalibration& test, const std::filesystem::path& directory,
                                  const std::string& rig_file, int views = 16,
                                  double pan_deg_max = 15.0, double tilt_deg_max = 10.0) {
  // The board 0.7 m ahead between the eyes, turned 25 deg about the vertical and tipped 15 deg.
  const std::filesystem::path experiment =
      test.write_experiment("[0.70, 0.0, 1.42]", "[0, 15, 25]", rig_file);
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> pan_deg(-pan_deg_max, pan_deg_max);
  std::uniform_real_distribution<double> tilt_deg(-tilt_deg_max, tilt_deg_max);
  std::ofstream poses(directory / "poses.yaml");
  poses << "poses:\n";
  for (int v = 0; v < views; ++v) {
    poses << "  - {neck_pan: " << pan_deg(rng) << ", neck_tilt: " << tilt_deg(rng) << "}\n";
  }
  poses.close();
  CommandResult result =
      run_cambio("calibrate capture '" + experiment.string() + "' --poses '" +
                 (directory / "poses.yaml").string() + "' --camera stereo --out '" +
                 (directory / "views").string() + "'");
  ASSERT_EQ(result.exit_code, 0) << result.output;
  const std::string last = std::to_string(views);
  ASSERT_TRUE(std::filesystem::exists(directory / "views" / ("left" + last + ".png")))
      << result.output;
  ASSERT_TRUE(std::filesystem::exists(directory / "views" / ("right" + last + ".png")))
      << result.output;
  ASSERT_TRUE(std::filesystem::exists(directory / "views" / ("pair" + last + ".yaml")))
      << result.output;
  result = run_cambio("calibrate stereo --images '" + (directory / "views").string() +
                      "' --board 9x6 --square-mm 25 --rig cambio --out '" +
                      (directory / "out").string() + "'");
  std::cout << result.output;
  ASSERT_EQ(result.exit_code, 0) << result.output;

  const config::RigConfig truth = config::load_rig(rig_file);
  const config::RigConfig calibrated = config::load_rig(
      rig_file, {{"camera_calibration", (directory / "out" / "camera_calibration.yaml").string()}});
  for (const char* name : {"left_eye", "right_eye"}) {
    const config::CameraConfig& want = *truth.find_camera(name);
    const config::CameraConfig& got = *calibrated.find_camera(name);
    // Where the board's views reach (the circle the image's height spans), and the corners,
    // which no view of the whole board reaches: there the fit extrapolates.
    const double lens_px = largest_lens_difference_px(want, got, 0.5 * want.height_px);
    const double corners_px = largest_lens_difference_px(want, got, 1e9);
    std::printf(
        "%s: focal %.3f %.3f px (rig %.3f), principal point %.2f %.2f px (rig %.2f %.2f), "
        "k1 %.4f k2 %.4f (rig %.4f %.4f), lens at most %.3f px off (%.3f px to the corners)\n",
        name, got.focal_x_px, got.focal_y_px, want.focal_x_px, got.principal_x_px,
        got.principal_y_px, want.principal_x_px, want.principal_y_px, got.distortion.k1,
        got.distortion.k2, want.distortion.k1, want.distortion.k2, lens_px, corners_px);
    EXPECT_NEAR(got.focal_x_px / want.focal_x_px, 1.0, 0.005) << name;
    EXPECT_NEAR(got.focal_y_px / want.focal_y_px, 1.0, 0.005) << name;
    EXPECT_NEAR(got.principal_x_px, want.principal_x_px, 1.0) << name;
    EXPECT_NEAR(got.principal_y_px, want.principal_y_px, 1.0) << name;
    EXPECT_LT(lens_px, 0.5) << name;
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

TEST_F(SimCalibration, StereoCaptureThenStereoCalibrationRecoversTheRigsCameras) {
  capture_and_calibrate_stereo(
      *this, directory_, std::string(CAMBIO_SOURCE_DIR) + "/firmware_config/rigs/cambio.yaml");
}

// The same rig with a wide-angle lens on each eye (the sim renders through them): the
// calibration must find those lenses, not a pinhole.
TEST_F(SimCalibration, StereoCalibrationThroughLensesRecoversTheirDistortion) {
  std::ifstream shipped(std::string(CAMBIO_SOURCE_DIR) + "/firmware_config/rigs/cambio.yaml");
  std::stringstream text;
  text << shipped.rdbuf();
  std::string rig = text.str();
  const std::string foveation = "    sim_foveation: {periphery_downscale: 4, fovea_px: 160}\n";
  const std::array<std::string, 2> lenses = {
      "    distortion: {k1: -0.28, k2: 0.07, p1: 0.001, p2: -0.0005, k3: 0}\n",
      "    distortion: {k1: -0.25, k2: 0.06, p1: -0.0008, p2: 0.0004, k3: 0}\n"};
  std::size_t at = 0;
  for (const std::string& lens : lenses) {
    at = rig.find(foveation, at);
    ASSERT_NE(at, std::string::npos) << "the shipped rig's camera entries changed";
    at += foveation.size();
    rig.insert(at, lens);
  }
  const std::filesystem::path rig_file = directory_ / "cambio_with_lenses.yaml";
  std::ofstream(rig_file) << rig;
  // A lens is only measured where the board has been: the head turns further, so that the board
  // reaches the image's edges, as a calibration of a real wide-angle camera must.
  capture_and_calibrate_stereo(*this, directory_, rig_file.string(), 28, 24.0, 17.0);
}

}  // namespace
}  // namespace cambio::testing
