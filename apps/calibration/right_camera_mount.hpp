#pragma once

#include <Eigen/Geometry>

#include "cambio/config/rig_config.hpp"

namespace cambio::app {

/// The pose of a link (a joint's name, or "base") in the base frame with every joint at zero.
/// Throws std::invalid_argument for a link the rig does not have.
Eigen::Isometry3d link_pose_at_zero(const config::RigConfig& rig, const std::string& link);

/// A rigid transform as a rig pose (xyz in metres, roll-pitch-yaw with R = Rz Ry Rx): the
/// inverse of config::to_isometry. At pitch +-90 deg (gimbal lock) roll takes the whole turn.
config::Pose pose_of(const Eigen::Isometry3d& X);

/// The right camera's mount X_PR (its optical frame in its parent link, the rig's
/// origin_xyz_m / origin_rpy) that puts it at `X_LR` from the left camera with every joint at
/// zero, the left camera's mount kept: the rig describes each camera on its own link, and a
/// stereo calibration measures only where one camera is from the other. The views must then have
/// been taken at the rig's zero pose (eyes parallel). `rig.stereo` names the pair; throws
/// std::invalid_argument when it is missing.
config::Pose right_camera_mount(const config::RigConfig& rig, const Eigen::Isometry3d& X_LR);

}  // namespace cambio::app
