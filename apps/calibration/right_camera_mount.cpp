#include "right_camera_mount.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "cambio/config/hardware_description.hpp"

namespace cambio::app {

Eigen::Isometry3d link_pose_at_zero(const config::RigConfig& rig, const std::string& link) {
  Eigen::Isometry3d X_BL = Eigen::Isometry3d::Identity();
  std::string current = link;
  // A loaded rig's joints form a tree rooted at base, so the walk ends within joints.size() steps.
  for (std::size_t steps = 0; current != "base"; ++steps) {
    const config::JointConfig* joint = rig.find_joint(current);
    if (joint == nullptr || steps > rig.joints.size()) {
      throw std::invalid_argument("rig '" + rig.name + "' has no link '" + current + "'");
    }
    // At zero the joint adds no motion: the link's frame is the joint's origin in its parent.
    X_BL = config::to_isometry(joint->origin) * X_BL;
    current = joint->parent;
  }
  return X_BL;
}

config::Pose pose_of(const Eigen::Isometry3d& X) {
  const Eigen::Matrix3d R = X.rotation();
  config::Pose pose;
  // R = Rz(yaw) Ry(pitch) Rx(roll): R(2,0) = -sin(pitch), R(2,1) / R(2,2) = tan(roll),
  // R(1,0) / R(0,0) = tan(yaw). Pitch from atan2, not asin: asin loses half the digits near
  // +-90 deg.
  const double cos_pitch = std::hypot(R(0, 0), R(1, 0));
  const double pitch = std::atan2(-R(2, 0), cos_pitch);
  double roll = std::atan2(R(2, 1), R(2, 2));
  double yaw = std::atan2(R(1, 0), R(0, 0));
  if (cos_pitch < 1e-12) {
    roll = std::atan2(-R(1, 2), R(1, 1));
    yaw = 0.0;
  }
  pose.rpy_rad = {roll, pitch, yaw};
  pose.xyz_m = {X.translation().x(), X.translation().y(), X.translation().z()};
  return pose;
}

config::Pose right_camera_mount(const config::RigConfig& rig, const Eigen::Isometry3d& X_LR) {
  if (!rig.stereo) {
    throw std::invalid_argument("rig '" + rig.name +
                                "' has no stereo section naming its left and right cameras");
  }
  const config::CameraConfig* left = rig.find_camera(rig.stereo->left_camera);
  const config::CameraConfig* right = rig.find_camera(rig.stereo->right_camera);
  if (left == nullptr || right == nullptr) {
    throw std::invalid_argument("rig '" + rig.name + "': its stereo cameras are not in it");
  }
  const Eigen::Isometry3d X_BL =
      link_pose_at_zero(rig, left->parent) * config::to_isometry(left->mount);
  const Eigen::Isometry3d X_BPr = link_pose_at_zero(rig, right->parent);
  return pose_of(X_BPr.inverse() * X_BL * X_LR);
}

}  // namespace cambio::app
