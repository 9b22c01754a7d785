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

FrameTransform to_frame_transform(const Eigen::Isometry3d& X) {
  const Eigen::Quaterniond q(X.rotation());
  const Eigen::Vector3d p = X.translation();
  return {{p.x(), p.y(), p.z()}, {q.x(), q.y(), q.z(), q.w()}};
}

FrameTransform joint_transform(const TfJoint& joint, double q_rad) {
  return to_frame_transform(joint.X_PJ * Eigen::AngleAxisd(q_rad, joint.axis_J));
}

}  // namespace cambio::ros2
