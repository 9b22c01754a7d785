#include "cambio/ros2/tf_tree.hpp"

#include <algorithm>
#include <stdexcept>

namespace cambio::ros2 {

TfTree make_tf_tree(const hal::HardwareInfo& hardware,
                    const std::vector<std::string>& joint_order) {
  TfTree tree;
  for (const hal::JointInfo& joint : hardware.joints) {
    const auto at = std::find(joint_order.begin(), joint_order.end(), joint.name);
    if (at == joint_order.end()) {
      throw std::invalid_argument("tf: joint '" + joint.name + "' is in no joint group");
    }
    tree.joints.push_back({joint.parent, joint.name, joint.X_PJ, joint.axis_J,
                           static_cast<std::size_t>(at - joint_order.begin())});
  }
  for (const hal::CameraInfo& camera : hardware.cameras) {
    tree.fixed.push_back({camera.parent_frame, camera.name + "_optical_frame", camera.X_PC});
  }
  return tree;
}

std::optional<Eigen::Isometry3d> pose_in_base(const TfTree& tree, std::string_view frame,
                                              std::span<const double> positions) {
  Eigen::Isometry3d X_BF = Eigen::Isometry3d::Identity();
  // Each step climbs one parent; more steps than frames would be a cycle.
  for (std::size_t steps = 0; steps <= tree.joints.size() + tree.fixed.size(); ++steps) {
    if (frame == "base") return X_BF;
    const auto joint = std::find_if(tree.joints.begin(), tree.joints.end(),
                                    [&](const TfJoint& j) { return j.child_frame == frame; });
    if (joint != tree.joints.end()) {
      if (joint->position_index >= positions.size()) return std::nullopt;
      X_BF =
          joint->X_PJ * Eigen::AngleAxisd(positions[joint->position_index], joint->axis_J) * X_BF;
      frame = joint->parent_frame;
      continue;
    }
    const auto fixed = std::find_if(tree.fixed.begin(), tree.fixed.end(),
                                    [&](const TfFixed& f) { return f.child_frame == frame; });
    if (fixed == tree.fixed.end()) return std::nullopt;
    X_BF = fixed->X_PC * X_BF;
    frame = fixed->parent_frame;
  }
  return std::nullopt;
}

FrameTransform to_frame_transform(const Eigen::Isometry3d& X) {
  const Eigen::Quaterniond q(X.rotation());
  const Eigen::Vector3d p = X.translation();
  return {{p.x(), p.y(), p.z()}, {q.x(), q.y(), q.z(), q.w()}};
}

FrameTransform joint_transform(const TfJoint& joint, double q_rad) {
  return to_frame_transform(joint.X_PJ * Eigen::AngleAxisd(q_rad, joint.axis_J));
}

}  // namespace cambio::ros2
