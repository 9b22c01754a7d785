#pragma once

#include <vector>

#include "cambio/behaviour/behaviour.hpp"

namespace cambio::behaviour::testing {

/// Actions that carry out nothing and remember what they were asked: the holds and the
/// saccades' directions from the eye (at the origin). Every action is "sent".
class RecordingActions final : public Actions {
 public:
  std::vector<Eigen::Vector3d> saccades;
  int holds = 0;
  ActionResult look_at_pixel(double, double) override { return {true, ""}; }
  ActionResult look_at_point(const Eigen::Vector3d&) override { return {true, ""}; }
  ActionResult saccade_to_pixel(double, double) override { return {true, ""}; }
  ActionResult saccade_to_point(const Eigen::Vector3d& p_W_m) override {
    saccades.push_back(p_W_m.normalized());
    return {true, ""};
  }
  ActionResult saccade_by_angles(double, double) override { return {true, ""}; }
  ActionResult pursue() override { return {true, ""}; }
  ActionResult hold() override {
    ++holds;
    return {true, ""};
  }
  ActionResult verge(bool) override { return {true, ""}; }
  ActionResult reach_fixated(control::ArmSide) override { return {true, ""}; }
  ActionResult reach_point(const Eigen::Vector3d&, control::ArmSide) override { return {true, ""}; }
  ActionResult grasp(control::ArmSide) override { return {true, ""}; }
  ActionResult release(control::ArmSide) override { return {true, ""}; }
  ActionResult move_joint(std::string_view, double) override { return {true, ""}; }
};

}  // namespace cambio::behaviour::testing
