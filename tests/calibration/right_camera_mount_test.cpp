// The rig pose of a rigid transform (the inverse of config::to_isometry), and the right camera's
// mount that reproduces a measured X_LR on the shipped rig.
#include "right_camera_mount.hpp"

#include <numbers>
#include <random>

#include <gtest/gtest.h>

#include "cambio/config/hardware_description.hpp"
#include "cambio/config/rig_loader.hpp"

namespace cambio::app {
namespace {

TEST(PoseOf, InvertsToIsometryOnRandomPosesAndAtGimbalLock) {
  std::mt19937 random(7);
  std::uniform_real_distribution<double> angle(-std::numbers::pi, std::numbers::pi);
  std::uniform_real_distribution<double> pitch(-1.5, 1.5);
  std::uniform_real_distribution<double> offset(-1.0, 1.0);
  std::vector<config::Pose> poses;
  for (int i = 0; i < 200; ++i) {
    poses.push_back({{offset(random), offset(random), offset(random)},
                     {angle(random), pitch(random), angle(random)}});
  }
  poses.push_back({{0, 0, 0}, {0.3, std::numbers::pi / 2, -0.2}});
  poses.push_back({{0, 0, 0}, {0.3, -std::numbers::pi / 2, 0.7}});
  for (const auto& pose : poses) {
    const Eigen::Isometry3d X = config::to_isometry(pose);
    EXPECT_TRUE(config::to_isometry(pose_of(X)).isApprox(X, 1e-12));
  }
}

TEST(RightCameraMount, PutsTheRightCameraAtXLRFromTheLeftWithJointsAtZero) {
  const config::RigConfig rig =
      config::load_rig(std::string(CAMBIO_SOURCE_DIR) + "/firmware_config/rigs/cambio.yaml");
  Eigen::Isometry3d X_LR = Eigen::Isometry3d::Identity();
  X_LR.linear() = Eigen::AngleAxisd(0.02, Eigen::Vector3d(0.3, -1.0, 0.2).normalized()).matrix();
  X_LR.translation() = Eigen::Vector3d(0.118, 0.002, -0.003);
  const config::Pose mount = right_camera_mount(rig, X_LR);

  // The shipped rig by hand: both eyes' pan joints sit on eye_tilt at y = +-0.06 m, each camera
  // 0.02 m forward of its joint, so the right eye's link is the left's moved by -0.12 m in y.
  const config::CameraConfig& left = *rig.find_camera("left_eye");
  Eigen::Isometry3d X_PrPl = Eigen::Isometry3d::Identity();
  X_PrPl.translation() = Eigen::Vector3d(0.0, 0.12, 0.0);
  const Eigen::Isometry3d expected = X_PrPl * config::to_isometry(left.mount) * X_LR;
  EXPECT_TRUE(config::to_isometry(mount).isApprox(expected, 1e-12));
  // The nominal pair (X_LR a pure 0.12 m along x) gives back the rig's own right mount.
  Eigen::Isometry3d nominal = Eigen::Isometry3d::Identity();
  nominal.translation() = Eigen::Vector3d(0.12, 0.0, 0.0);
  EXPECT_TRUE(config::to_isometry(right_camera_mount(rig, nominal))
                  .isApprox(config::to_isometry(rig.find_camera("right_eye")->mount), 1e-12));
}

TEST(RightCameraMount, RefusesARigWithoutAStereoPair) {
  config::RigConfig rig =
      config::load_rig(std::string(CAMBIO_SOURCE_DIR) + "/firmware_config/rigs/cambio.yaml");
  rig.stereo.reset();
  EXPECT_THROW((void)right_camera_mount(rig, Eigen::Isometry3d::Identity()), std::invalid_argument);
}

}  // namespace
}  // namespace cambio::app
