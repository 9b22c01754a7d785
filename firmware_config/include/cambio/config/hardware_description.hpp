#pragma once

#include <Eigen/Geometry>

#include "cambio/config/rig_config.hpp"
#include "cambio/hal/hardware_info.hpp"

namespace cambio::config {

/// A rig file's pose as a rigid transform: R = Rz(yaw) * Ry(pitch) * Rx(roll) (URDF's
/// convention), then the translation.
Eigen::Isometry3d to_isometry(const Pose& pose);

/// The HAL's description of the hardware, from a loaded (validated) rig: joints ordered parents
/// first, groups with limits, cameras with intrinsics and mounts, touch sensors, buses.
hal::HardwareInfo hardware_description(const RigConfig& rig);

}  // namespace cambio::config
