// `cambio calibrate stereo` on views rendered with known intrinsics, distortion and pose
// (chessboard_renderer: the projection written out here, not OpenCV's): the recovered values must
// match the truth (focal length within 0.5 %, baseline within 1 mm, rotation within 0.1 deg), in
// the rig's calibration file as the rig loader reads it and in the ROS camera_info files.
#include <algorithm>
#include <cmath>
#include <filesystem>
#include <iostream>
#include <map>
#include <numbers>
#include <regex>
#include <string>

#include <gtest/gtest.h>
#include <yaml-cpp/yaml.h>

#include "../apps/run_cambio.hpp"
#include "cambio/config/hardware_description.hpp"
#include "cambio/config/rig_loader.hpp"
#include "rendered_stereo_views.hpp"

namespace cambio::testing {
namespace {

constexpr double kDegPerRad = 180.0 / std::numbers::pi;
constexpr int kViews = 16;

/// A link's pose in base with every joint at zero, walked over the HAL's joints (parents first):
/// the loader's view of the rig, apart from the command's own kinematics.
Eigen::Isometry3d link_in_base(const hal::HardwareInfo& hardware, const std::string& link) {
  std::map<std::string, Eigen::Isometry3d> X_B{{"base", Eigen::Isometry3d::Identity()}};
  for (const auto& joint : hardware.joints) X_B[joint.name] = X_B.at(joint.parent) * joint.X_PJ;
  return X_B.at(link);
}

/// X_LR of the rig's stereo pair at zero, from the cameras' mounts as loaded.
Eigen::Isometry3d loaded_X_LR(const config::RigConfig& rig) {
  const hal::HardwareInfo hardware = config::hardware_description(rig);
  Eigen::Isometry3d X_BL;
  Eigen::Isometry3d X_BR;
  for (const auto& camera : hardware.cameras) {
    const Eigen::Isometry3d X_BC = link_in_base(hardware, camera.parent_frame) * camera.X_PC;
    if (camera.name == rig.stereo->left_camera) X_BL = X_BC;
    if (camera.name == rig.stereo->right_camera) X_BR = X_BC;
  }
  return X_BL.inverse() * X_BR;
}

double rotation_error_deg(const Eigen::Isometry3d& a, const Eigen::Isometry3d& b) {
  return Eigen::AngleAxisd(a.rotation().transpose() * b.rotation()).angle() * kDegPerRad;
}

class RenderedStereoCalibration : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    directory_ = std::filesystem::temp_directory_path() /
                 ("cambio_calibrate_rendered_" + std::to_string(::getpid()));
    std::filesystem::remove_all(directory_);
    const TrueStereoPair pair = true_stereo_pair();
    write_rendered_views(pair, TrueBoard{}, board_poses(pair, TrueBoard{}, kViews),
                         directory_ / "views");
    result_ = run_cambio("calibrate stereo --images '" + (directory_ / "views").string() +
                         "' --board 9x6 --square-mm 25 --rig cambio --out '" +
                         (directory_ / "out").string() + "'");
    std::cout << result_.output;
  }
  static void TearDownTestSuite() { std::filesystem::remove_all(directory_); }

  static inline std::filesystem::path directory_;
  static inline CommandResult result_;
};

TEST_F(RenderedStereoCalibration, UsesEveryViewAndFitsToAFractionOfAPixel) {
  ASSERT_EQ(result_.exit_code, 0) << result_.output;
  EXPECT_EQ(result_.output.find("refused"), std::string::npos);
  for (int v = 1; v <= kViews; ++v) {
    const std::string id = (v < 10 ? "0" : "") + std::to_string(v);
    EXPECT_NE(result_.output.find("view " + id + ": RMS "), std::string::npos) << id;
  }
  std::smatch match;
  ASSERT_TRUE(std::regex_search(result_.output, match, std::regex("overall: RMS ([0-9.]+) px")));
  // Exact geometry, 8-bit grey levels: corner noise is a few hundredths of a pixel.
  EXPECT_LT(std::stod(match[1]), 0.1);
}

TEST_F(RenderedStereoCalibration, RigCalibrationFileLoadsAsTheTruth) {
  ASSERT_EQ(result_.exit_code, 0) << result_.output;
  const std::string file = (directory_ / "out" / "camera_calibration.yaml").string();
  const config::RigConfig rig =
      config::load_rig(std::string(CAMBIO_SOURCE_DIR) + "/firmware_config/rigs/cambio.yaml",
                       {{"camera_calibration", file}});
  const TrueStereoPair truth = true_stereo_pair();
  for (const auto& [name, camera] :
       {std::pair{"left_eye", truth.left}, {"right_eye", truth.right}}) {
    const config::CameraConfig& loaded = *rig.find_camera(name);
    EXPECT_NEAR(loaded.focal_x_px / camera.focal_x_px, 1.0, 0.005) << name;
    EXPECT_NEAR(loaded.focal_y_px / camera.focal_y_px, 1.0, 0.005) << name;
    EXPECT_NEAR(loaded.principal_x_px, camera.principal_x_px, 1.0) << name;
    EXPECT_NEAR(loaded.principal_y_px, camera.principal_y_px, 1.0) << name;
    // k1, k2 and k3 trade off against each other over the field the boards cover, so the
    // coefficients are not compared one by one: the displacement they model is, over the
    // central 60 % of the image (the boards, seen whole by both cameras, never reach the outer
    // parts, where a fit extrapolates), in pixels.
    double distortion_error_px = 0.0;
    for (double u = 0.2; u <= 0.8; u += 0.05) {
      for (double v = 0.2; v <= 0.8; v += 0.05) {
        const Eigen::Vector2d p((u * camera.width_px - camera.principal_x_px) / camera.focal_x_px,
                                (v * camera.height_px - camera.principal_y_px) / camera.focal_y_px);
        const Eigen::Vector2d d = distort(loaded.distortion, p) - distort(camera.distortion, p);
        distortion_error_px = std::max(distortion_error_px, camera.focal_x_px * d.norm());
      }
    }
    EXPECT_LT(distortion_error_px, 0.5) << name;
    std::printf(
        "%s: focal error %.4f %% (x), %.4f %% (y); principal point %.3f, %.3f px; "
        "distortion at most %.3f px off\n",
        name, 100.0 * (loaded.focal_x_px / camera.focal_x_px - 1.0),
        100.0 * (loaded.focal_y_px / camera.focal_y_px - 1.0),
        loaded.principal_x_px - camera.principal_x_px,
        loaded.principal_y_px - camera.principal_y_px, distortion_error_px);
  }
  const Eigen::Isometry3d X_LR = loaded_X_LR(rig);
  const double baseline_error_m = X_LR.translation().norm() - truth.X_LR.translation().norm();
  const double translation_error_m = (X_LR.translation() - truth.X_LR.translation()).norm();
  const double rotation_deg = rotation_error_deg(X_LR, truth.X_LR);
  std::printf("X_LR: baseline error %.4f mm, translation error %.4f mm, rotation error %.5f deg\n",
              1000.0 * baseline_error_m, 1000.0 * translation_error_m, rotation_deg);
  EXPECT_LT(std::abs(baseline_error_m), 0.001);
  EXPECT_LT(translation_error_m, 0.002);
  EXPECT_LT(rotation_deg, 0.1);
}

TEST_F(RenderedStereoCalibration, RosCameraInfoFilesHoldTheTruth) {
  ASSERT_EQ(result_.exit_code, 0) << result_.output;
  const TrueStereoPair truth = true_stereo_pair();
  for (const auto& [name, camera] :
       {std::pair{"left_eye", truth.left}, {"right_eye", truth.right}}) {
    const YAML::Node info =
        YAML::LoadFile((directory_ / "out" / (std::string(name) + ".yaml")).string());
    EXPECT_EQ(info["camera_name"].as<std::string>(), name);
    EXPECT_EQ(info["image_width"].as<int>(), 640);
    EXPECT_EQ(info["image_height"].as<int>(), 480);
    EXPECT_EQ(info["distortion_model"].as<std::string>(), "plumb_bob");
    const auto K = info["camera_matrix"]["data"].as<std::vector<double>>();
    ASSERT_EQ(K.size(), 9U);
    EXPECT_NEAR(K[0] / camera.focal_x_px, 1.0, 0.005);
    EXPECT_NEAR(K[4] / camera.focal_y_px, 1.0, 0.005);
    EXPECT_EQ(info["distortion_coefficients"]["data"].as<std::vector<double>>().size(), 5U);
    const auto R = info["rectification_matrix"]["data"].as<std::vector<double>>();
    ASSERT_EQ(R.size(), 9U);
    const Eigen::Matrix3d R_rect =
        Eigen::Map<const Eigen::Matrix<double, 3, 3, Eigen::RowMajor>>(R.data());
    EXPECT_LT((R_rect * R_rect.transpose() - Eigen::Matrix3d::Identity()).norm(), 1e-9);
    EXPECT_EQ(info["projection_matrix"]["rows"].as<int>(), 3);
    EXPECT_EQ(info["projection_matrix"]["cols"].as<int>(), 4);
  }
  // The right projection's Tx = -fx' * baseline (ROS's CameraInfo), fx' the rectified focal.
  const auto P =
      YAML::LoadFile((directory_ / "out" / "right_eye.yaml").string())["projection_matrix"]["data"]
          .as<std::vector<double>>();
  ASSERT_EQ(P.size(), 12U);
  EXPECT_NEAR(-P[3] / P[0], truth.X_LR.translation().norm(), 0.001);
  // Rectified rows: the two rectified frames differ by the baseline along x only.
  const auto P_left =
      YAML::LoadFile((directory_ / "out" / "left_eye.yaml").string())["projection_matrix"]["data"]
          .as<std::vector<double>>();
  EXPECT_DOUBLE_EQ(P_left[3], 0.0);
  EXPECT_DOUBLE_EQ(P[7], 0.0);
}

}  // namespace
}  // namespace cambio::testing
