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

/// The CiA 402 drive behind a joint: what a CAN backend needs to address it, convert units and
/// write its parameters (position limits and max velocity come from the joint's limits).
struct JointDriveInfo {
  int node_id = 0;                          ///< CANopen node id, 1..127.
  double gear_ratio = 1.0;                  ///< Motor turns per joint turn.
  std::int64_t encoder_counts_per_rev = 0;  ///< Motor encoder counts per motor turn.
  /// CiA 402 following error window (0x6065): the drive faults (EMCY 0x8611) when its position
  /// lags its demand by more than this. 0 = leave the drive's own setting.
  double following_error_window_rad = 0.0;
  /// Cyclic synchronous position (default) or cyclic synchronous velocity.
  CommandMode mode = CommandMode::kPosition;
};

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
  std::optional<JointDriveInfo> drive;  ///< Set when the rig gives the joint a CAN drive.
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

struct CanBusInfo {
  std::string name;       ///< The rig's name for it (groups refer to it).
  std::string interface;  ///< Kernel interface, e.g. "can0", "vcan0".
  std::int64_t bitrate_bit_s = 1'000'000;
  bool fd = false;
  std::int64_t data_bitrate_bit_s = 0;
};

/// Everything about the hardware that every backend shares, as ros2_control's HardwareInfo:
/// the joint tree with limits and drives, the groups and which backend drives each, cameras
/// with intrinsics and mounts, touch sensors and buses. Built by the config layer from the rig
/// file; the HAL knows nothing of files. What only one backend needs (the sim's scene) reaches
/// that backend through the maker the application registers.
struct HardwareInfo {
  std::string name;
  std::vector<JointInfo> joints;       ///< Parents come before their children.
  std::vector<JointGroupInfo> groups;  ///< Joint order of each group = its read()/write() order.
  std::vector<CameraInfo> cameras;
  std::optional<StereoPairInfo> stereo;
  std::vector<TouchSensorInfo> touch_sensors;
  std::vector<CanBusInfo> can_buses;

  const JointInfo* find_joint(std::string_view joint_name) const {
    return find(joints, joint_name);
  }
  const JointGroupInfo* find_group(std::string_view group_name) const {
    return find(groups, group_name);
  }
  const CameraInfo* find_camera(std::string_view camera_name) const {
    return find(cameras, camera_name);
  }
  const CanBusInfo* find_can_bus(std::string_view bus_name) const {
    return find(can_buses, bus_name);
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
