#include "cambio/control/arm_chain.hpp"

#include <cmath>
#include <stdexcept>

namespace cambio::control {
namespace {

constexpr double kTolerance = 1e-9;

struct Expected {
  const char* role;
  Eigen::Vector3d axis;
};

std::string describe(const Eigen::Vector3d& v) {
  return "[" + std::to_string(v.x()) + ", " + std::to_string(v.y()) + ", " + std::to_string(v.z()) +
         "]";
}

}  // namespace

double ArmChain::hand_m(double opening_rad) const {
  // One fingertip at R_z(opening) (tip_x, tip_y) from the gripper's axis; the mirrored one at
  // R_z(-opening) (tip_x, -tip_y): their midpoint lies on the hand's x axis.
  return wrist_to_gripper_m + fingers.tip_x_m * std::cos(opening_rad) -
         fingers.tip_y_m * std::sin(opening_rad);
}

ArmChain find_arm_chain(const hal::HardwareInfo& hardware, const std::string& group_name) {
  const hal::JointGroupInfo* group = hardware.find_group(group_name);
  const std::string where = "arm '" + group_name + "': ";
  if (group == nullptr) throw std::invalid_argument(where + "no such joint group");
  if (group->joints.size() != 5) {
    throw std::invalid_argument(where +
                                "expected five joints (shoulder yaw, shoulder pitch, elbow, "
                                "wrist, gripper), found " +
                                std::to_string(group->joints.size()));
  }
  const std::array<Expected, 5> expected{{
      {"shoulder yaw", Eigen::Vector3d::UnitZ()},
      {"shoulder pitch", Eigen::Vector3d::UnitY()},
      {"elbow", Eigen::Vector3d::UnitY()},
      {"wrist", Eigen::Vector3d::UnitY()},
      {"gripper", Eigen::Vector3d::UnitZ()},
  }};
  ArmChain chain;
  chain.group = group_name;
  int rig_first = 0;
  for (const auto& g : hardware.groups) {
    if (g.name == group_name) break;
    rig_first += static_cast<int>(g.joints.size());
  }
  std::array<Eigen::Vector3d, 5> offsets;
  for (std::size_t k = 0; k < 5; ++k) {
    const std::string& name = group->joints[k];
    const hal::JointInfo* joint = hardware.find_joint(name);
    if (joint == nullptr) throw std::invalid_argument(where + "unknown joint '" + name + "'");
    const std::string what = where + expected[k].role + " '" + name + "' ";
    const std::string parent = k == 0 ? std::string("base") : group->joints[k - 1];
    if (joint->parent != parent) {
      throw std::invalid_argument(what + "must hang from '" + parent + "', found '" +
                                  joint->parent + "'");
    }
    if (!(joint->axis_J - expected[k].axis).isZero(kTolerance) ||
        !joint->X_PJ.linear().isIdentity(kTolerance)) {
      throw std::invalid_argument(what + "must turn about " + describe(expected[k].axis) +
                                  " with no rotation of its frame, found axis " +
                                  describe(joint->axis_J));
    }
    offsets[k] = joint->X_PJ.translation();
    // Everything after the shoulder lies along the links' x: the arm stays in one plane.
    if (k >= 1 && (std::abs(offsets[k].y()) > kTolerance || std::abs(offsets[k].z()) > kTolerance ||
                   offsets[k].x() < (k == 1 ? -kTolerance : kTolerance) ||
                   (k == 1 && offsets[k].x() > kTolerance))) {
      throw std::invalid_argument(what + "has origin " + describe(offsets[k]) +
                                  (k == 1 ? ", expected the shoulder yaw's origin"
                                          : ", expected a positive offset along x only"));
    }
    for (int t = 0; t < static_cast<int>(hardware.joints.size()); ++t) {
      if (hardware.joints[static_cast<std::size_t>(t)].name == name) chain.joints[k] = t;
    }
    chain.rig[k] = rig_first + static_cast<int>(k);
    chain.limits[k] = joint->limits;
    chain.names[k] = name;
  }
  chain.shoulder_W = offsets[0];
  chain.upper_arm_m = offsets[2].x();
  chain.forearm_m = offsets[3].x();
  chain.wrist_to_gripper_m = offsets[4].x();
  for (const auto& sensor : hardware.touch_sensors) {
    if (sensor.parent != chain.names[4]) continue;
    chain.fingers = {sensor.fingertip_x_m, sensor.fingertip_y_m};
    chain.has_touch_sensor = true;
  }
  return chain;
}

}  // namespace cambio::control
