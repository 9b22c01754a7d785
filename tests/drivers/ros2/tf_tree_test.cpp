#include "cambio/ros2/tf_tree.hpp"

#include <gtest/gtest.h>

#include <numbers>

namespace cambio::ros2 {
namespace {

// A pan-tilt with a camera: pan about z at (0, 0, 1), tilt about y 0.1 m above it, the camera's
// optical frame 0.05 m ahead of the tilt link.
hal::HardwareInfo pan_tilt() {
  hal::HardwareInfo hardware;
  hal::JointInfo pan;
  pan.name = "pan";
  pan.X_PJ.translation() = Eigen::Vector3d(0, 0, 1);
  pan.axis_J = Eigen::Vector3d::UnitZ();
  hal::JointInfo tilt;
  tilt.name = "tilt";
  tilt.parent = "pan";
  tilt.X_PJ.translation() = Eigen::Vector3d(0, 0, 0.1);
  tilt.axis_J = Eigen::Vector3d::UnitY();
  hardware.joints = {pan, tilt};
  hal::CameraInfo camera;
  camera.name = "eye";
  camera.parent_frame = "tilt";
  camera.X_PC.translation() = Eigen::Vector3d(0.05, 0, 0);
  hardware.cameras = {camera};
  return hardware;
}

TEST(TfTree, PlacesEveryFrameInBaseAsTheChainWrittenOutByHand) {
  // The joint states list tilt before pan: the tree follows the names, not the rig's order.
  const TfTree tree = make_tf_tree(pan_tilt(), {"tilt", "pan"});
  const double pan = std::numbers::pi / 2;
  const double tilt = 0.3;
  const std::vector<double> positions = {tilt, pan};
  // Pan a quarter turn left: the camera, 0.05 m ahead of the tilt axis, ends at +y; tilting
  // about y lowers what is ahead, keeping the point on the axis where it is.
  const Eigen::Isometry3d expected =
      Eigen::Translation3d(0, 0, 1) * Eigen::AngleAxisd(pan, Eigen::Vector3d::UnitZ()) *
      Eigen::Translation3d(0, 0, 0.1) * Eigen::AngleAxisd(tilt, Eigen::Vector3d::UnitY()) *
      Eigen::Translation3d(0.05, 0, 0);
  const auto X_BC = pose_in_base(tree, "eye_optical_frame", positions);
  ASSERT_TRUE(X_BC);
  EXPECT_TRUE(X_BC->isApprox(expected, 1e-12));
  EXPECT_NEAR(X_BC->translation().y(), 0.05 * std::cos(tilt), 1e-12);
  EXPECT_NEAR(X_BC->translation().z(), 1.1 - 0.05 * std::sin(tilt), 1e-12);
  EXPECT_TRUE(pose_in_base(tree, "base", positions)->isApprox(Eigen::Isometry3d::Identity()));
}

TEST(TfTree, AFrameTheTreeLacksHasNoPoseAndAJointWithoutAPositionIsRefused) {
  const TfTree tree = make_tf_tree(pan_tilt(), {"pan", "tilt"});
  EXPECT_FALSE(pose_in_base(tree, "nowhere", std::vector<double>{0, 0}));
  EXPECT_FALSE(pose_in_base(tree, "tilt", std::vector<double>{0}));
  EXPECT_THROW(make_tf_tree(pan_tilt(), {"pan"}), std::invalid_argument);
}

}  // namespace
}  // namespace cambio::ros2
