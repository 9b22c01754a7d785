#include "interim_gaze_actions.hpp"

namespace cambio::app {
namespace {

using behaviour::ActionResult;
using control::GazeAction;
using control::GazeTarget;
using control::GazeTargetKind;

GazeTarget pixel(double u_px, double v_px) {
  GazeTarget target;
  target.kind = GazeTargetKind::kPixel;
  target.pixel_px = {u_px, v_px};
  return target;
}

GazeTarget point(const Eigen::Vector3d& p_W_m) {
  GazeTarget target;
  target.kind = GazeTargetKind::kPoint;
  target.point_W_m = {p_W_m.x(), p_W_m.y(), p_W_m.z()};
  return target;
}

ActionResult no_arms() {
  return {false, "this run has no arm controller"};
}

}  // namespace

ActionResult InterimGazeActions::send(GazeAction action, const GazeTarget& target) {
  control::GazeCommand command;
  command.sequence = ++sequence_;
  command.action = action;
  command.target = target;
  command.verge = verge_;
  commands_.write(command);
  return {true, ""};
}

ActionResult InterimGazeActions::look_at_pixel(double u_px, double v_px) {
  return send(GazeAction::kFixate, pixel(u_px, v_px));
}
ActionResult InterimGazeActions::look_at_point(const Eigen::Vector3d& p_W_m) {
  return send(GazeAction::kFixate, point(p_W_m));
}
ActionResult InterimGazeActions::saccade_to_pixel(double u_px, double v_px) {
  return send(GazeAction::kSaccade, pixel(u_px, v_px));
}
ActionResult InterimGazeActions::saccade_to_point(const Eigen::Vector3d& p_W_m) {
  return send(GazeAction::kSaccade, point(p_W_m));
}
ActionResult InterimGazeActions::saccade_by_angles(double pan_rad, double tilt_rad) {
  GazeTarget target;
  target.kind = GazeTargetKind::kAngles;
  target.angles_rad = {pan_rad, tilt_rad};
  return send(GazeAction::kSaccade, target);
}
ActionResult InterimGazeActions::pursue() {
  return send(GazeAction::kPursue, GazeTarget{});
}
ActionResult InterimGazeActions::hold() {
  return send(GazeAction::kHold, GazeTarget{});
}
ActionResult InterimGazeActions::verge(bool on) {
  verge_ = on;
  return {true, "applies from the next gaze command"};
}
ActionResult InterimGazeActions::reach_fixated(control::ArmSide) {
  return no_arms();
}
ActionResult InterimGazeActions::reach_point(const Eigen::Vector3d&, control::ArmSide) {
  return no_arms();
}
ActionResult InterimGazeActions::grasp(control::ArmSide) {
  return no_arms();
}
ActionResult InterimGazeActions::release(control::ArmSide) {
  return no_arms();
}
ActionResult InterimGazeActions::move_joint(std::string_view joint_name, double) {
  return {false, "moving one joint ('" + std::string(joint_name) +
                     "') comes with control::RobotActions; this run's interim actions cannot"};
}

}  // namespace cambio::app
