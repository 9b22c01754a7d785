// `cambio calibrate hand-eye` on views of a fixed chessboard rendered at random head poses with
// the rig's true camera mount (chessboard_renderer: the projection written out here, not
// OpenCV's), the joints read as the sim's drives read them (quantised to 65536 counts a turn):
// the mount it writes must be the rig's to 1 mm and 0.1 deg. (A reading that also missed the
// servo's 0.0002 rad jitter, an image and a reading taken apart, costs 2-4 mm: the camera sits
// 2 cm from its pan axis and the views turn it by a few tens of degrees.) And its refusals: too
// few views, motions about one axis, a view without a reading of a joint that moves the camera,
// a camera the rig does not have.
#include <cmath>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <map>
#include <numbers>
#include <random>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <yaml-cpp/yaml.h>
#include <opencv2/imgcodecs.hpp>

#include "../apps/run_cambio.hpp"
#include "cambio/config/hardware_description.hpp"
#include "cambio/config/rig_loader.hpp"
#include "cambio/config/shipped_config.hpp"
#include "chessboard_renderer.hpp"

namespace cambio::testing {
namespace {

constexpr double kDegPerRad = 180.0 / std::numbers::pi;
constexpr double kEncoderQuantum_rad = 2.0 * std::numbers::pi / 65536.0;

/// Every link's pose in base at `q` (joint name -> rad, 0 for the others), walked over the HAL's
/// joints (parents first): X_PL(q) = X_PJ Rotation(axis, q), apart from the command's kinematics.
std::map<std::string, Eigen::Isometry3d> links_in_base(const hal::HardwareInfo& hardware,
                                                       const std::map<std::string, double>& q) {
  std::map<std::string, Eigen::Isometry3d> X_B{{"base", Eigen::Isometry3d::Identity()}};
  for (const auto& joint : hardware.joints) {
    const auto it = q.find(joint.name);
    const double angle = it != q.end() ? it->second : 0.0;
    X_B[joint.name] = X_B.at(joint.parent) * joint.X_PJ *
                      Eigen::Isometry3d(Eigen::AngleAxisd(angle, joint.axis_J));
  }
  return X_B;
}

class RenderedHandEye : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    hardware_ = config::hardware_description(
        config::load_rig(config::find_shipped_config("rigs/cambio.yaml")));
    for (const auto& camera : hardware_.cameras) {
      if (camera.name == "left_eye") camera_info_ = camera;
    }
    camera_.focal_x_px = camera_info_.intrinsics.focal_x_px;
    camera_.focal_y_px = camera_info_.intrinsics.focal_y_px;
    camera_.principal_x_px = camera_info_.intrinsics.principal_x_px;
    camera_.principal_y_px = camera_info_.intrinsics.principal_y_px;
    camera_.width_px = camera_info_.intrinsics.width_px;
    camera_.height_px = camera_info_.intrinsics.height_px;
    // The board 0.7 m ahead of the left eye at zero, facing it (z into the board, x to the robot's
    // right, y down), its first inner corner up and left so that the board is centred.
    const Eigen::Isometry3d X_BC0 =
        links_in_base(hardware_, {}).at(camera_info_.parent_frame) * camera_info_.X_PC;
    // Turned 30 deg about the vertical and tipped back 20 deg, as a board is held: a board square
    // to the camera leaves its tilt unobservable to first order (its image shrinks by cos).
    Eigen::Matrix3d facing;
    facing << 0, 0, 1, -1, 0, 0, 0, -1, 0;
    X_BT_.linear() = Eigen::AngleAxisd(30.0 / kDegPerRad, Eigen::Vector3d::UnitZ()) *
                     Eigen::AngleAxisd(-20.0 / kDegPerRad, Eigen::Vector3d::UnitY()) * facing;
    X_BT_.translation() = X_BC0.translation() + Eigen::Vector3d(0.7, 0.1, 0.0625);
    directory_ = std::filesystem::temp_directory_path() /
                 ("cambio_hand_eye_rendered_" + std::to_string(::getpid()));
    std::filesystem::remove_all(directory_);
  }
  static void TearDownTestSuite() { std::filesystem::remove_all(directory_); }

  /// Renders `count` views into `folder` at random poses of `joints` (within +-`range_deg`) that
  /// show the whole board, with noisy readings; `omit` is left out of every readings file.
  static void render_views(const std::filesystem::path& folder, int count,
                           const std::vector<std::string>& joints, double range_deg,
                           const std::string& omit = "") {
    std::filesystem::create_directories(folder);
    std::mt19937 random(static_cast<unsigned>(count * 7919 + joints.size()));
    std::uniform_real_distribution<double> angle(-range_deg / kDegPerRad, range_deg / kDegPerRad);
    const BoardRenderer renderer(camera_, 3);
    const TrueBoard board;
    for (int view = 1; view <= count;) {
      // Every joint that moves the left eye is read; those not varied stay at zero.
      std::map<std::string, double> q{
          {"neck_pan", 0.0}, {"neck_tilt", 0.0}, {"eye_tilt", 0.0}, {"left_eye_pan", 0.0}};
      for (const std::string& joint : joints) q[joint] = angle(random);
      const Eigen::Isometry3d X_BC =
          links_in_base(hardware_, q).at(camera_info_.parent_frame) * camera_info_.X_PC;
      const Eigen::Isometry3d X_CT = X_BC.inverse() * X_BT_;
      bool whole = true;
      for (int row = 0; row < board.inner_rows; ++row) {
        for (int column = 0; column < board.inner_columns; ++column) {
          const auto p = project_px(
              camera_, X_CT * Eigen::Vector3d(column * board.square_m, row * board.square_m, 0));
          whole = whole && p && p->x() > 30 && p->y() > 30 && p->x() < camera_.width_px - 31 &&
                  p->y() < camera_.height_px - 31;
        }
      }
      if (!whole) continue;
      const std::string id = (view < 10 ? "0" : "") + std::to_string(view);
      ASSERT_TRUE(
          cv::imwrite((folder / ("view" + id + ".png")).string(), renderer.render(board, X_CT)));
      std::ofstream readings(folder / ("view" + id + ".yaml"));
      readings.precision(17);
      readings << "joints_rad:\n";
      for (const auto& [joint, value] : q) {
        if (joint == omit) continue;
        const double read = std::round(value / kEncoderQuantum_rad) * kEncoderQuantum_rad;
        readings << "  " << joint << ": " << read << "\n";
      }
      ASSERT_TRUE(readings.good());
      ++view;
    }
  }

  static CommandResult calibrate(const std::filesystem::path& views, const std::string& camera,
                                 const std::filesystem::path& out) {
    return run_cambio("calibrate hand-eye --views '" + views.string() +
                      "' --board 9x6 --square-mm 25 --rig cambio --camera " + camera + " --out '" +
                      out.string() + "'");
  }

  static inline hal::HardwareInfo hardware_;
  static inline hal::CameraInfo camera_info_;
  static inline TrueCamera camera_;
  static inline Eigen::Isometry3d X_BT_ = Eigen::Isometry3d::Identity();
  static inline std::filesystem::path directory_;
};

TEST_F(RenderedHandEye, RecoversTheRigsMountToAMillimetreAndATenthOfADegree) {
  const std::vector<std::string> head{"neck_pan", "neck_tilt", "eye_tilt", "left_eye_pan"};
  render_views(directory_ / "views", 12, head, 12.0);
  const CommandResult result = calibrate(directory_ / "views", "left_eye", directory_ / "out");
  std::cout << result.output;
  ASSERT_EQ(result.exit_code, 0) << result.output;
  const YAML::Node file = YAML::LoadFile((directory_ / "out" / "camera_calibration.yaml").string());
  const YAML::Node left = file["cameras"]["left_eye"];
  config::Pose mount;
  for (std::size_t i = 0; i < 3; ++i) {
    mount.xyz_m[i] = left["origin_xyz_m"][i].as<double>();
    mount.rpy_rad[i] = left["origin_rpy_deg"][i].as<double>() / kDegPerRad;
  }
  const Eigen::Isometry3d X_PC = config::to_isometry(mount);
  const double offset_mm = (X_PC.translation() - camera_info_.X_PC.translation()).norm() * 1000.0;
  const double angle_deg =
      Eigen::AngleAxisd(X_PC.rotation().transpose() * camera_info_.X_PC.rotation()).angle() *
      kDegPerRad;
  std::printf("hand-eye: mount off the rig's by %.3f mm and %.4f deg\n", offset_mm, angle_deg);
  EXPECT_LT(offset_mm, 1.0);
  EXPECT_LT(angle_deg, 0.1);
  // The other camera keeps the rig's values: the file can replace the rig's calibration.
  EXPECT_DOUBLE_EQ(file["cameras"]["right_eye"]["focal_x_px"].as<double>(), 554.256);
  EXPECT_DOUBLE_EQ(file["cameras"]["right_eye"]["origin_xyz_m"][0].as<double>(), 0.02);
}

TEST_F(RenderedHandEye, RefusesTooFewViewsOneAxisOfMotionAMissingReadingAndAnUnknownCamera) {
  render_views(directory_ / "few", 3, {"neck_pan", "neck_tilt"}, 10.0);
  CommandResult result = calibrate(directory_ / "few", "left_eye", directory_ / "out_few");
  EXPECT_EQ(result.exit_code, 1) << result.output;
  EXPECT_NE(result.output.find("3 views have the whole board; at least 5"), std::string::npos)
      << result.output;
  render_views(directory_ / "pan_only", 6, {"neck_pan"}, 10.0);
  result = calibrate(directory_ / "pan_only", "left_eye", directory_ / "out_pan");
  EXPECT_EQ(result.exit_code, 1) << result.output;
  EXPECT_NE(result.output.find("about one axis only"), std::string::npos) << result.output;
  render_views(directory_ / "no_tilt", 5, {"neck_pan", "neck_tilt"}, 10.0, "neck_tilt");
  result = calibrate(directory_ / "no_tilt", "left_eye", directory_ / "out_tilt");
  EXPECT_EQ(result.exit_code, 2) << result.output;
  EXPECT_NE(result.output.find("no reading of joint 'neck_tilt', which moves camera left_eye"),
            std::string::npos)
      << result.output;
  result = calibrate(directory_ / "few", "left_eyes", directory_ / "out_camera");
  EXPECT_EQ(result.exit_code, 2) << result.output;
  EXPECT_NE(result.output.find("has no camera 'left_eyes' (its cameras: left_eye, right_eye)"),
            std::string::npos)
      << result.output;
}

}  // namespace
}  // namespace cambio::testing
