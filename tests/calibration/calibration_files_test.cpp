// The files `calibrate stereo` writes, parsed back: the rig's camera_calibration file (with
// yaml-cpp and with the rig loader) and the ROS camera_info files.
#include "calibration_files.hpp"

#include <filesystem>
#include <fstream>

#include <gtest/gtest.h>
#include <yaml-cpp/yaml.h>

#include "cambio/config/hardware_description.hpp"
#include "cambio/config/rig_loader.hpp"
#include "right_camera_mount.hpp"

namespace cambio::app {
namespace {

const std::string kRigPath = std::string(CAMBIO_SOURCE_DIR) + "/firmware_config/rigs/cambio.yaml";

StereoCalibration example_calibration() {
  StereoCalibration calibration;
  calibration.left = {
      640, 480, 533.123456789, 534.5, 341.25, 234.75, {-0.28, 0.09, 0.0012, -0.0004, -0.011}, 0.3};
  calibration.right = {
      640, 480, 536.0, 535.25, 326.5, 249.125, {-0.27, 0.07, -0.0002, 0.0007, 0.02}, 0.32};
  calibration.X_LR.linear() =
      Eigen::AngleAxisd(0.01, Eigen::Vector3d(0.1, 1.0, -0.2).normalized()).matrix();
  calibration.X_LR.translation() = Eigen::Vector3d(0.121, -0.0015, 0.0008);
  calibration.views = {{"01", 0.2, 0.3, 0.255}};
  calibration.rms_px = 0.41;
  calibration.rectification.R_right = {1, 0, 0, 0, 1, 0, 0, 0, 1};
  calibration.rectification.P_right = {500, 0, 320, -60.5, 0, 500, 240, 0, 0, 0, 1, 0};
  return calibration;
}

TEST(RigCalibrationFile, ParsesBackToTheFittedNumbers) {
  const config::RigConfig rig = config::load_rig(kRigPath);
  const StereoCalibration calibration = example_calibration();
  const config::Pose mount = right_camera_mount(rig, calibration.X_LR);
  const YAML::Node file =
      YAML::Load(rig_camera_calibration_yaml(rig, calibration, mount, {"cambio ...", "9x6"}));
  const YAML::Node left = file["cameras"]["left_eye"];
  EXPECT_EQ(left["width_px"].as<int>(), 640);
  EXPECT_DOUBLE_EQ(left["focal_x_px"].as<double>(), 533.123456789);
  EXPECT_EQ(left["principal_point_px"].as<std::vector<double>>(),
            (std::vector<double>{341.25, 234.75}));
  EXPECT_DOUBLE_EQ(left["distortion"]["k3"].as<double>(), -0.011);
  EXPECT_FALSE(left["origin_xyz_m"]) << "the left camera keeps the rig's mount";
  const YAML::Node right = file["cameras"]["right_eye"];
  EXPECT_DOUBLE_EQ(right["distortion"]["p2"].as<double>(), 0.0007);
  const auto xyz = right["origin_xyz_m"].as<std::vector<double>>();
  ASSERT_EQ(xyz.size(), 3U);
  EXPECT_NEAR(xyz[1], mount.xyz_m[1], 1e-12);
  EXPECT_EQ(right["origin_rpy_deg"].as<std::vector<double>>().size(), 3U);
}

TEST(RigCalibrationFile, TheRigLoaderReadsItBackIntoTheCameras) {
  const config::RigConfig nominal = config::load_rig(kRigPath);
  const StereoCalibration calibration = example_calibration();
  const auto path = std::filesystem::temp_directory_path() /
                    ("cambio_calibration_" + std::to_string(::getpid()) + ".yaml");
  std::ofstream(path) << rig_camera_calibration_yaml(
      nominal, calibration, right_camera_mount(nominal, calibration.X_LR), {"cambio ...", "9x6"});
  const config::RigConfig rig = config::load_rig(kRigPath, {{"camera_calibration", path.string()}});
  std::filesystem::remove(path);

  const hal::HardwareInfo hardware = config::hardware_description(rig);
  const hal::CameraInfo& left = hardware.cameras[0];
  ASSERT_EQ(left.name, "left_eye");
  EXPECT_NEAR(left.intrinsics.focal_x_px, 533.123456789, 1e-9);
  EXPECT_NEAR(left.intrinsics.principal_y_px, 234.75, 1e-12);
  EXPECT_NEAR(left.distortion.k1, -0.28, 1e-12);
  EXPECT_NEAR(left.distortion.p1, 0.0012, 1e-12);
  EXPECT_TRUE(left.X_PC.isApprox(config::to_isometry(nominal.find_camera("left_eye")->mount)));
  const hal::CameraInfo& right = hardware.cameras[1];
  EXPECT_NEAR(right.intrinsics.focal_y_px, 535.25, 1e-9);
  EXPECT_NEAR(right.distortion.k3, 0.02, 1e-12);
  // The loaded mounts put the right camera at X_LR from the left (both eyes' links at y = +-0.06 m
  // on eye_tilt, so the left link is the right's moved by +0.12 m in y).
  Eigen::Isometry3d X_PrPl = Eigen::Isometry3d::Identity();
  X_PrPl.translation() = Eigen::Vector3d(0.0, 0.12, 0.0);
  const Eigen::Isometry3d X_LR = left.X_PC.inverse() * X_PrPl.inverse() * right.X_PC;
  EXPECT_TRUE(X_LR.isApprox(calibration.X_LR, 1e-9));
}

TEST(RosCameraInfoFile, HasCameraCalibrationParsersKeysAndNumbers) {
  const StereoCalibration calibration = example_calibration();
  const YAML::Node info = YAML::Load(ros_camera_info_yaml("right_eye", calibration.right,
                                                          calibration.rectification.R_right,
                                                          calibration.rectification.P_right));
  EXPECT_EQ(info["image_width"].as<int>(), 640);
  EXPECT_EQ(info["image_height"].as<int>(), 480);
  EXPECT_EQ(info["camera_name"].as<std::string>(), "right_eye");
  EXPECT_EQ(info["camera_matrix"]["rows"].as<int>(), 3);
  EXPECT_EQ(info["camera_matrix"]["cols"].as<int>(), 3);
  EXPECT_EQ(info["camera_matrix"]["data"].as<std::vector<double>>(),
            (std::vector<double>{536.0, 0, 326.5, 0, 535.25, 249.125, 0, 0, 1}));
  EXPECT_EQ(info["distortion_model"].as<std::string>(), "plumb_bob");
  EXPECT_EQ(info["distortion_coefficients"]["cols"].as<int>(), 5);
  EXPECT_EQ(info["distortion_coefficients"]["data"].as<std::vector<double>>(),
            (std::vector<double>{-0.27, 0.07, -0.0002, 0.0007, 0.02}));
  EXPECT_EQ(info["rectification_matrix"]["data"].as<std::vector<double>>().size(), 9U);
  EXPECT_EQ(info["projection_matrix"]["cols"].as<int>(), 4);
  EXPECT_DOUBLE_EQ(info["projection_matrix"]["data"][3].as<double>(), -60.5);
}

}  // namespace
}  // namespace cambio::app
