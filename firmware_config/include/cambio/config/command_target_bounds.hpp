#pragma once

#include <cmath>
#include <numbers>

namespace cambio::config {

// What a command's target may be (where to look, what to reach), the same wherever the command
// comes from: an experiment file, the console, a behaviour. Every entry refuses a target outside
// these bounds at once, with its reason, rather than hand a loop a command it can only drop.

/// A point target's coordinates in the base frame (m), gaze or reach: within a kilometre. Beyond it
/// every direction is the same for a 12 cm baseline, and a coordinate of 1e300 is finite while its
/// square is not.
inline constexpr double kMaxTargetCoordinate_m = 1000.0;

/// An angular displacement of the gaze, pan or tilt (rad): less than a quarter turn, where the
/// image plane still has a direction for it (tan(90 deg) has none; beyond it tan turns back).
inline constexpr double kMaxGazeDisplacementRad = 0.5 * std::numbers::pi - 1e-3;

/// A pixel target lies on the dominant eye's image: u in [0, width - 1], v in [0, height - 1].
inline bool pixel_on_image(double u_px, double v_px, int width_px, int height_px) {
  return std::isfinite(u_px) && std::isfinite(v_px) && u_px >= 0.0 && v_px >= 0.0 &&
         u_px <= width_px - 1 && v_px <= height_px - 1;
}

}  // namespace cambio::config
