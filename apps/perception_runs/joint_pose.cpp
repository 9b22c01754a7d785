#include "joint_pose.hpp"

#include <algorithm>
#include <iostream>

namespace cambio::app {

bool apply_joint_poses(config::RigConfig& rig, const std::vector<JointPose>& poses) {
  for (const auto& pose : poses) {
    auto it =
        std::find_if(rig.joints.begin(), rig.joints.end(),
                     [&](const config::JointConfig& joint) { return joint.name == pose.joint; });
    if (it == rig.joints.end()) {
      std::string known;
      for (const auto& joint : rig.joints) known += (known.empty() ? "" : ", ") + joint.name;
      std::cerr << "cambio render: no joint named '" << pose.joint << "' in rig " << rig.name
                << " (joints: " << known << ")\n";
      return false;
    }
    if (pose.position_rad < it->min_position_rad || pose.position_rad > it->max_position_rad) {
      std::cerr << "cambio render: " << pose.joint << " = " << pose.position_rad
                << " rad is outside its limits [" << it->min_position_rad << ", "
                << it->max_position_rad << "] rad\n";
      return false;
    }
    it->initial_position_rad = pose.position_rad;
  }
  return true;
}

}  // namespace cambio::app
