#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include <Eigen/Geometry>

#include "cambio/hal/camera.hpp"
#include "cambio/hal/joint_group.hpp"

namespace cambio::hal {

/// One revolute joint of the rig tree. Every joint moves a link named after it; its parent is
/// "base" (the robot's root, fixed in the world) or another joint's link.
struct JointInfo {
  std::string name;
  std::string group;
  std::string parent = "base";
  /// The joint frame in the parent link frame at zero position (the child link frame coincides
  /// with it at zero): X_PL(q) = X_PJ * Rotation(axis_J, q).
  Eigen::Isometry3d X_PJ = Eigen::Isometry3d::Identity();
  Eigen::Vector3d axis_J = Eigen::Vector3d::UnitZ();  ///< Unit vector in the joint frame.
  JointLimits limits;
  double initial_position_rad = 0.0;
};

struct StereoPairInfo {
  std::string left_camera;
  std::string right_camera;
  double baseline_m = 0.0;
};

struct TouchSensorInfo {
  std::string name;
  std::string backend;
  std::string parent;  ///< The link whose geometry is the end effector.
  /// The middle of one fingertip's front face in the parent link's frame at zero opening (x along
  /// the finger, y off the gripper's midline; the other finger mirrors it to -y), m.
  double fingertip_x_m = 0.0;
  double fingertip_y_m = 0.0;
};

/// Everything about the hardware that every backend shares, as ros2_control's HardwareInfo:
/// the joint tree with limits, the groups and which backend drives each, cameras with
/// intrinsics and mounts, touch sensors. Built by the config layer from the rig file; the HAL
/// knows nothing of files. What only one backend needs (the sim's scene, the CANopen buses and
/// drives) reaches that backend through the maker the application registers, and the backend
/// checks it itself (BackendFactory::check).
struct HardwareInfo {
  std::string name;
  std::vector<JointInfo> joints;       ///< Parents come before their children.
  std::vector<JointGroupInfo> groups;  ///< Joint order of each group = its read()/write() order.
  std::vector<CameraInfo> cameras;
  std::optional<StereoPairInfo> stereo;
  std::vector<TouchSensorInfo> touch_sensors;

  const JointInfo* find_joint(std::string_view joint_name) const {
    return find(joints, joint_name);
  }
  const JointGroupInfo* find_group(std::string_view group_name) const {
    return find(groups, group_name);
  }
  const CameraInfo* find_camera(std::string_view camera_name) const {
    return find(cameras, camera_name);
  }

 private:
  template <class T>
  static const T* find(const std::vector<T>& items, std::string_view name) {
    for (const T& item : items) {
      if (item.name == name) return &item;
    }
    return nullptr;
  }
};

}  // namespace cambio::hal
