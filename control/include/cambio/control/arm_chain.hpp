#pragma once

#include <array>
#include <string>

#include <Eigen/Core>

#include "cambio/hal/hardware_info.hpp"

namespace cambio::control {

/// The fingers' geometry, from the gripper joint's origin in its link frame (x along the
/// fingers, at zero opening): where the middle of one fingertip's front face is. The other
/// finger mirrors it (the sim's mimic finger). From the rig's touch sensor on the gripper
/// (touch_sensors.<name>.fingertip_xy_m), which the sim also builds its fingers from.
struct FingerGeometry {
  double tip_x_m = 0.0;  ///< Along the finger.
  double tip_y_m = 0.0;  ///< Off the gripper's midline, at zero opening.
};

/// An arm as the reach needs it: a shoulder yaw (about z), then three pitch joints (shoulder,
/// elbow, wrist; about y, positive lowering) in one vertical plane, then the gripper (its opening
/// angle about the wrist link's z). Found on a rig group by find_arm_chain(); the closed-form
/// inverse kinematics and the reach check (arm_reach_check.hpp) rely on exactly this shape.
///
/// In the arm's plane (after the yaw), angles are measured downward from the horizontal: the
/// upper arm points at a1 = q_pitch, the forearm at a2 = a1 + q_elbow, the hand at
/// a3 = a2 + q_wrist (the hand's pitch, 0 level, > 0 pointing down).
struct ArmChain {
  std::string group;  ///< The rig group ("left_arm").
  /// Tree indices (HardwareInfo order) of yaw, pitch, elbow, wrist, gripper.
  std::array<int, 5> joints{};
  /// Rig indices (JointTargetFrame order) of the same joints.
  std::array<int, 5> rig{};
  std::array<std::string, 5> names;                      ///< The same joints' names.
  Eigen::Vector3d shoulder_W = Eigen::Vector3d::Zero();  ///< On the yaw axis (base frame, m).
  double upper_arm_m = 0.0;                              ///< Shoulder pitch to elbow.
  double forearm_m = 0.0;                                ///< Elbow to wrist.
  double wrist_to_gripper_m = 0.0;                       ///< Wrist to the gripper's axis.
  std::array<hal::JointLimits, 5> limits{};
  /// The fingertips of the touch sensor on the gripper; has_touch_sensor false (and the tips at
  /// the gripper's axis) when no touch sensor names the gripper as its parent.
  FingerGeometry fingers;
  bool has_touch_sensor = false;

  /// Wrist to the fingertips' midpoint along the hand at gripper opening `opening_rad`: the
  /// fingertips turn about the gripper's axis, so they come back as the gripper opens.
  double hand_m(double opening_rad) const;
  /// The furthest the fingertips reach from the shoulder (arm and hand straight).
  double reach_m(double opening_rad) const { return upper_arm_m + forearm_m + hand_m(opening_rad); }
};

/// The arm of rig group `group_name`. `rig_order` is the rig's joints in rig order (the groups'
/// joints concatenated). Throws std::invalid_argument, saying what does not fit, for a group
/// that is not five joints shaped as ArmChain describes (axes, parents, offsets along x).
ArmChain find_arm_chain(const hal::HardwareInfo& hardware, const std::string& group_name);

}  // namespace cambio::control
