#pragma once

#include <Eigen/Geometry>
#include <array>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "cambio/hal/hardware_info.hpp"

namespace cambio::ros2 {

/// A joint's link as tf sees it: the transform parent -> child moves with the joint's position.
struct TfJoint {
  std::string parent_frame;
  std::string child_frame;
  Eigen::Isometry3d X_PJ = Eigen::Isometry3d::Identity();  ///< The joint frame at zero.
  Eigen::Vector3d axis_J = Eigen::Vector3d::UnitZ();
  std::size_t position_index = 0;  ///< Where the joint's position sits in a joint-state sample.
};

/// A frame fixed to its parent (a camera's optical frame on its eye).
struct TfFixed {
  std::string parent_frame;
  std::string child_frame;
  Eigen::Isometry3d X_PC = Eigen::Isometry3d::Identity();
};

/// The rig's kinematic tree for /tf and /tf_static: one frame per joint (its child link, named
/// after the joint, as in the rig file), the root "base", and each camera's optical frame
/// (`<camera>_optical_frame`, ROS's optical convention: z forward, x right, y down, which is the
/// rig's own).
struct TfTree {
  std::vector<TfJoint> joints;
  std::vector<TfFixed> fixed;
};

/// Builds the tree of `hardware`; `joint_order` is the order of the joint-state samples. Throws
/// std::invalid_argument for a joint of the hardware that `joint_order` lacks.
TfTree make_tf_tree(const hal::HardwareInfo& hardware, const std::vector<std::string>& joint_order);

/// The pose of `frame` (a joint's link, a fixed frame, or "base") in "base" with the joints at
/// `positions` (the joint states' order); nullopt for a frame the tree does not have.
std::optional<Eigen::Isometry3d> pose_in_base(const TfTree& tree, std::string_view frame,
                                              std::span<const double> positions);

/// A transform as geometry_msgs/Transform carries it.
struct FrameTransform {
  std::array<double, 3> translation_m{};
  std::array<double, 4> rotation_xyzw{0.0, 0.0, 0.0, 1.0};
};

FrameTransform to_frame_transform(const Eigen::Isometry3d& X);
/// The transform parent -> child of `joint` at position `q_rad`: X_PJ * Rotation(axis_J, q).
FrameTransform joint_transform(const TfJoint& joint, double q_rad);

}  // namespace cambio::ros2
