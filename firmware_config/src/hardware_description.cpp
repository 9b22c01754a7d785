#include "cambio/config/hardware_description.hpp"

#include <set>
#include <stdexcept>

namespace cambio::config {

namespace {

hal::JointLimits limits_of(const JointConfig& joint) {
  return {joint.min_position_rad, joint.max_position_rad, joint.max_velocity_rad_s,
          joint.max_acceleration_rad_s2, joint.max_effort_nm};
}

hal::JointInfo joint_info(const JointConfig& joint) {
  hal::JointInfo info;
  info.name = joint.name;
  info.group = joint.group;
  info.parent = joint.parent;
  info.X_PJ = to_isometry(joint.origin);
  info.axis_J = Eigen::Vector3d(joint.axis[0], joint.axis[1], joint.axis[2]).normalized();
  info.limits = limits_of(joint);
  info.initial_position_rad = joint.initial_position_rad;
  return info;
}

}  // namespace

Eigen::Isometry3d to_isometry(const Pose& pose) {
  Eigen::Isometry3d X = Eigen::Isometry3d::Identity();
  X.linear() = (Eigen::AngleAxisd(pose.rpy_rad[2], Eigen::Vector3d::UnitZ()) *
                Eigen::AngleAxisd(pose.rpy_rad[1], Eigen::Vector3d::UnitY()) *
                Eigen::AngleAxisd(pose.rpy_rad[0], Eigen::Vector3d::UnitX()))
                   .toRotationMatrix();
  X.translation() = Eigen::Vector3d(pose.xyz_m[0], pose.xyz_m[1], pose.xyz_m[2]);
  return X;
}

hal::HardwareInfo hardware_description(const RigConfig& rig) {
  hal::HardwareInfo hardware;
  hardware.name = rig.name;

  // Parents first: repeatedly take the joints whose parent is already placed.
  std::set<std::string> placed{"base"};
  while (hardware.joints.size() < rig.joints.size()) {
    const std::size_t before = hardware.joints.size();
    for (const auto& joint : rig.joints) {
      if (placed.count(joint.name) != 0 || placed.count(joint.parent) == 0) continue;
      hardware.joints.push_back(joint_info(joint));
      placed.insert(joint.name);
    }
    if (hardware.joints.size() == before) {
      throw std::invalid_argument("rig '" + rig.name +
                                  "': a joint's parent chain does not reach base");
    }
  }

  for (const auto& group : rig.groups) {
    hal::JointGroupInfo info;
    info.name = group.name;
    info.backend = group.backend;
    info.joints = group.joints;
    info.rate_hz = group.rate_hz;
    for (const auto& joint_name : group.joints) {
      const JointConfig* joint = rig.find_joint(joint_name);
      if (joint == nullptr) {
        throw std::invalid_argument("rig '" + rig.name + "': group '" + group.name +
                                    "' names unknown joint '" + joint_name + "'");
      }
      info.limits.push_back(limits_of(*joint));
    }
    hardware.groups.push_back(std::move(info));
  }

  const LoopConfig* camera_loop = rig.find_loop("camera");
  for (const auto& camera : rig.cameras) {
    hal::CameraInfo info;
    info.name = camera.name;
    info.backend = camera.backend;
    info.parent_frame = camera.parent;
    info.X_PC = to_isometry(camera.mount);
    info.intrinsics = {camera.width_px,   camera.height_px,      camera.focal_x_px,
                       camera.focal_y_px, camera.principal_x_px, camera.principal_y_px};
    info.distortion = camera.distortion;
    info.format = camera.format == PixelFormatConfig::kGrey8 ? hal::PixelFormat::kGrey8
                                                             : hal::PixelFormat::kRgb8;
    if (camera_loop != nullptr) info.rate_hz = camera_loop->rate_hz;
    hardware.cameras.push_back(std::move(info));
  }
  if (rig.stereo) {
    hardware.stereo = hal::StereoPairInfo{rig.stereo->left_camera, rig.stereo->right_camera,
                                          rig.stereo->baseline_m};
  }
  for (const auto& sensor : rig.touch_sensors) {
    hardware.touch_sensors.push_back(
        {sensor.name, sensor.backend, sensor.parent, sensor.fingertip_x_m, sensor.fingertip_y_m});
  }
  return hardware;
}

}  // namespace cambio::config
