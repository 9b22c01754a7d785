#pragma once

#include <array>

#include "cambio/config/scene_config.hpp"

namespace cambio::sim {

/// Where a scripted object is at sim time `t_s` (seconds since the run started): its scene pose
/// moved along its motion (waypoints: piecewise linear, holding the ends; oscillate: sine along
/// the axis; circle: about the scene position in the plane normal to the axis). Orientation
/// stays the scene's. Real-time safe.
std::array<double, 3> scripted_position(const config::SceneObjectConfig& object,
                                        double t_s) noexcept;

}  // namespace cambio::sim
