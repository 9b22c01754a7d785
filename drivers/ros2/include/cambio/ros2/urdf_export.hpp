#pragma once

#include <string>
#include <string_view>

#include "cambio/hal/hardware_info.hpp"

namespace cambio::ros2 {

/// The rig as a URDF, for /robot_description and `cambio export urdf`: a link per joint, named
/// after it as /tf names its frames (root "base"); revolute joints with the rig's origins, axes
/// and limits; each camera's optical frame as a fixed link `<camera>_optical_frame`. Visuals are
/// the simulator's link shapes in URDF's primitives: a cylinder from each joint to each child
/// joint (a MuJoCo capsule's body, with a sphere at its far end), an eyeball on each camera, a
/// sphere on a link with neither. The grippers' fingers are not drawn.
std::string make_urdf(const hal::HardwareInfo& hardware, std::string_view robot_name);

}  // namespace cambio::ros2
