#pragma once

#include <cmath>
#include <numbers>
#include <sstream>
#include <string>
#include <utility>

#include "cambio/behaviour/behaviour.hpp"

// What RobotActions says when it refuses or adjusts an action; shared by robot_actions.cpp and
// robot_actions_arms.cpp only.

namespace cambio::app::action_text {

inline behaviour::ActionResult refused(std::string why) {
  return {false, std::move(why)};
}

// An angle as people read it; one too large for degrees (1e308 rad) is said as given.
inline std::string degrees(double rad) {
  std::ostringstream out;
  const double deg = rad * 180.0 / std::numbers::pi;
  if (!std::isfinite(deg)) {
    out << rad << " rad";
  } else {
    out.precision(1);
    out << std::fixed << deg << " deg";
  }
  return out.str();
}

inline std::string point_text(const Eigen::Vector3d& p) {
  std::ostringstream out;
  out << "(" << p.x() << ", " << p.y() << ", " << p.z() << ") m";
  return out.str();
}

}  // namespace cambio::app::action_text
