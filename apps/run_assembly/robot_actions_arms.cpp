#include "robot_actions.hpp"

#include <algorithm>
#include <cmath>

#include "cambio/config/command_target_bounds.hpp"
#include "cambio/config/echoed_text.hpp"
#include "cambio/config/map_reader.hpp"
#include "robot_action_text.hpp"

// RobotActions' arm actions, and the move of one joint (head or arm) within its limits.

namespace cambio::app {
namespace {

using action_text::degrees;
using action_text::point_text;
using action_text::refused;

}  // namespace

behaviour::ActionResult RobotActions::reach_fixated(control::ArmSide arm) {
  control::ArmCommand command;
  command.action = control::ArmAction::kReach;
  command.arm = arm;
  command.target = control::ReachTargetKind::kFixation;
  return send(command);
}

behaviour::ActionResult RobotActions::reach_point(const Eigen::Vector3d& p_W_m,
                                                  control::ArmSide arm) {
  if (!p_W_m.allFinite()) return refused("the point " + point_text(p_W_m) + " is not finite");
  if (p_W_m.cwiseAbs().maxCoeff() > config::kMaxTargetCoordinate_m) {
    return refused("the point " + point_text(p_W_m) +
                   " is beyond any arm: every coordinate within a kilometre of the robot");
  }
  control::ArmCommand command;
  command.action = control::ArmAction::kReach;
  command.arm = arm;
  command.target = control::ReachTargetKind::kPoint;
  command.point_W_m = {p_W_m.x(), p_W_m.y(), p_W_m.z()};
  return send(command);
}

behaviour::ActionResult RobotActions::grasp(control::ArmSide arm) {
  control::ArmCommand command;
  command.action = control::ArmAction::kGrasp;
  command.arm = arm;
  return send(command);
}

behaviour::ActionResult RobotActions::release(control::ArmSide arm) {
  control::ArmCommand command;
  command.action = control::ArmAction::kRelease;
  command.arm = arm;
  return send(command);
}

std::vector<RobotActions::Joint>::const_iterator RobotActions::find_joint(
    std::string_view joint_name, std::string& why) const {
  const auto joint = std::find_if(joints_.begin(), joints_.end(),
                                  [&](const Joint& j) { return j.name == joint_name; });
  if (joint == joints_.end()) {
    std::vector<std::string> names;
    for (const Joint& j : joints_) names.push_back(j.name);
    why = "no joint " + config::in_quotes(joint_name);
    if (const auto near = config::closest_name(joint_name, names)) {
      why += "; did you mean " + config::in_quotes(*near) + "?";
    }
  }
  return joint;
}

behaviour::ActionResult RobotActions::move_joint(std::string_view joint_name, double position_rad) {
  std::string why;
  const auto joint = find_joint(joint_name, why);
  if (joint == joints_.end()) return refused(why);
  if (!std::isfinite(position_rad)) return refused(joint->name + ": the angle is not finite");
  const double clamped =
      std::clamp(position_rad, joint->limits.min_position_rad, joint->limits.max_position_rad);
  std::string note;
  if (clamped != position_rad) {
    note = joint->name + ": " + degrees(position_rad) + " is beyond its " +
           (clamped > position_rad ? "lower" : "upper") + " limit; clamped to " + degrees(clamped);
  }
  const int index = static_cast<int>(joint - joints_.begin());
  behaviour::ActionResult result;
  if (joint->head) {
    control::GazeCommand command;
    command.action = control::GazeAction::kMoveJoint;
    command.joint_rig_index = index;
    command.position_rad = clamped;
    result = send(command);
  } else {
    control::ArmCommand command;
    command.action = control::ArmAction::kMoveJoint;
    command.joint_rig_index = index;
    command.position_rad = clamped;
    result = send(command);
  }
  if (result.sent) result.message = note;
  return result;
}

}  // namespace cambio::app
