#pragma once

// A pose to render the robot at: joint angles set as a rig's initial positions.

#include <string>
#include <vector>

#include "cambio/config/rig_config.hpp"

namespace cambio::app {

struct JointPose {
  std::string joint;
  double position_rad = 0.0;
};

/// Sets each pose's joint's initial position in `rig`. False (the reason printed, naming the
/// rig's joints or the limits) when a joint is not in the rig or an angle is outside its limits;
/// `rig` may then hold the poses before that one.
bool apply_joint_poses(config::RigConfig& rig, const std::vector<JointPose>& poses);

}  // namespace cambio::app
