#include "robot_actions.hpp"

#include <algorithm>
#include <cmath>
#include <sstream>
#include <stdexcept>

#include "cambio/config/command_target_bounds.hpp"
#include "robot_action_text.hpp"

// RobotActions' construction, its gaze actions and feature requests, and the sending every
// action ends in; the arm actions and joint moves are in robot_actions_arms.cpp.

namespace cambio::app {
namespace {

using action_text::degrees;
using action_text::point_text;
using action_text::refused;

// Sequence numbers of the actions start far above the experiment script's (which counts from
// 1), so the gaze loop never takes an action for a command it has already applied.
constexpr std::uint64_t kFirstSequence = std::uint64_t{1} << 40;

}  // namespace

RobotActions::RobotActions(const hal::HardwareInfo& hardware, Setup setup, Channels channels)
    : image_width_px_(setup.image_width_px),
      image_height_px_(setup.image_height_px),
      channels_(channels),
      verge_(setup.verge),
      gaze_sequence_(kFirstSequence),
      arm_sequence_(kFirstSequence) {
  if (channels_.gaze == nullptr) throw std::invalid_argument("robot actions: no gaze channel");
  for (const std::string& name : setup.rig_joint_order) {
    const hal::JointInfo* joint = hardware.find_joint(name);
    if (joint == nullptr) throw std::invalid_argument("robot actions: no joint '" + name + "'");
    const bool head = std::find(setup.head_joints.begin(), setup.head_joints.end(), name) !=
                      setup.head_joints.end();
    joints_.push_back({name, joint->limits, head});
  }
}

behaviour::ActionResult RobotActions::send(control::GazeCommand command) {
  std::lock_guard lock(mutex_);
  command.sequence = ++gaze_sequence_;
  if (command.action != control::GazeAction::kVerge) command.verge = verge_;
  channels_.gaze->write(command);
  return {true, {}};
}

behaviour::ActionResult RobotActions::send(control::ArmCommand command) {
  if (channels_.arms == nullptr) return refused("this run has no arm controller");
  std::lock_guard lock(mutex_);
  command.sequence = ++arm_sequence_;
  channels_.arms->write(command);
  return {true, {}};
}

behaviour::ActionResult RobotActions::pixel_command(control::GazeAction action, double u_px,
                                                    double v_px) {
  // The experiment loader's rule (config/command_target_bounds.hpp), so a pixel means the same
  // typed at the console as written in a file.
  if (!config::pixel_on_image(u_px, v_px, image_width_px_, image_height_px_)) {
    std::ostringstream why;
    why << "pixel (" << u_px << ", " << v_px << ") is outside the dominant eye's "
        << image_width_px_ << "x" << image_height_px_ << " image (u in [0, " << image_width_px_ - 1
        << "], v in [0, " << image_height_px_ - 1 << "])";
    return refused(why.str());
  }
  control::GazeCommand command;
  command.action = action;
  command.target.kind = control::GazeTargetKind::kPixel;
  command.target.pixel_px = {u_px, v_px};
  return send(command);
}

behaviour::ActionResult RobotActions::point_command(control::GazeAction action,
                                                    const Eigen::Vector3d& p_W_m) {
  if (!p_W_m.allFinite()) return refused("the point " + point_text(p_W_m) + " is not finite");
  if (p_W_m.cwiseAbs().maxCoeff() > config::kMaxTargetCoordinate_m) {
    return refused("the point " + point_text(p_W_m) +
                   " is not one the eyes can fixate: every coordinate within a kilometre of the "
                   "robot");
  }
  control::GazeCommand command;
  command.action = action;
  command.target.kind = control::GazeTargetKind::kPoint;
  command.target.point_W_m = {p_W_m.x(), p_W_m.y(), p_W_m.z()};
  return send(command);
}

behaviour::ActionResult RobotActions::look_at_pixel(double u_px, double v_px) {
  return pixel_command(control::GazeAction::kFixate, u_px, v_px);
}

behaviour::ActionResult RobotActions::look_at_point(const Eigen::Vector3d& p_W_m) {
  return point_command(control::GazeAction::kFixate, p_W_m);
}

behaviour::ActionResult RobotActions::saccade_to_pixel(double u_px, double v_px) {
  return pixel_command(control::GazeAction::kSaccade, u_px, v_px);
}

behaviour::ActionResult RobotActions::saccade_to_point(const Eigen::Vector3d& p_W_m) {
  return point_command(control::GazeAction::kSaccade, p_W_m);
}

behaviour::ActionResult RobotActions::saccade_by_angles(double pan_rad, double tilt_rad) {
  constexpr double kLargest = config::kMaxGazeDisplacementRad;
  if (!std::isfinite(pan_rad) || !std::isfinite(tilt_rad) || std::abs(pan_rad) > kLargest ||
      std::abs(tilt_rad) > kLargest) {
    return refused("angles (" + degrees(pan_rad) + ", " + degrees(tilt_rad) +
                   ") must be finite and less than a quarter turn from the gaze");
  }
  control::GazeCommand command;
  command.action = control::GazeAction::kSaccade;
  command.target.kind = control::GazeTargetKind::kAngles;
  command.target.angles_rad = {pan_rad, tilt_rad};
  return send(command);
}

behaviour::ActionResult RobotActions::pursue() {
  control::GazeCommand command;
  command.action = control::GazeAction::kPursue;
  return send(command);
}

behaviour::ActionResult RobotActions::hold() {
  control::GazeCommand command;
  command.action = control::GazeAction::kHold;
  return send(command);
}

behaviour::ActionResult RobotActions::verge(bool on) {
  {
    std::lock_guard lock(mutex_);
    verge_ = on;
  }
  control::GazeCommand command;
  command.action = control::GazeAction::kVerge;
  command.verge = on;
  return send(command);
}

behaviour::ActionResult RobotActions::request_features(const perception::FeatureRequest& features) {
  if (channels_.features == nullptr) return refused("this run takes no feature requests");
  std::lock_guard lock(mutex_);
  channels_.features->write(features);
  return {true, {}};
}

bool RobotActions::verging() const {
  std::lock_guard lock(mutex_);
  return verge_;
}

std::uint64_t RobotActions::gaze_commands_sent() const {
  std::lock_guard lock(mutex_);
  return gaze_sequence_ - kFirstSequence;
}

std::uint64_t RobotActions::arm_commands_sent() const {
  std::lock_guard lock(mutex_);
  return arm_sequence_ - kFirstSequence;
}

}  // namespace cambio::app
