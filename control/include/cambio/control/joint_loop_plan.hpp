#pragma once

#include <cstddef>
#include <string>
#include <vector>

#include "cambio/hal/joint_group.hpp"

namespace cambio::control {

/// One joint loop of a rig and the groups it drives.
struct JointLoopPlan {
  std::string name;  ///< "joint", or "joint.<group>[+<group>...]".
  double rate_hz = 0.0;
  std::vector<std::size_t> groups;  ///< Indices into the groups planned, in their order.
};

/// Which joint loops drive `groups`: the groups at the rig-wide `joint_rate_hz` (or with
/// rate_hz 0) share the loop "joint", so a rig whose groups set no rate of their own keeps its
/// one loop and its name; groups at another rate share one loop per rate, named after them
/// ("joint.left_arm+right_arm"), as ros2_control runs a hardware component at its own rate.
/// "joint" comes first, the others in the order of their first group. Throws
/// std::invalid_argument on a rate that is not positive and finite.
std::vector<JointLoopPlan> plan_joint_loops(const std::vector<hal::JointGroupInfo>& groups,
                                            double joint_rate_hz);

}  // namespace cambio::control
