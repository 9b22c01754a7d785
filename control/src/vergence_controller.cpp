#include "cambio/control/vergence_controller.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace cambio::control {

VergenceController::VergenceController(const VergenceParams& params) : params_(params) {
  if (!(params_.focal_px > 0.0)) throw std::invalid_argument("vergence: focal_px must be > 0");
  if (!(params_.gain > 0.0 && params_.gain <= 1.0)) {
    throw std::invalid_argument("vergence: gain must be in (0, 1]");
  }
  if (!(params_.max_step_rad > 0.0)) {
    throw std::invalid_argument("vergence: max_step_rad must be > 0");
  }
}

double VergenceController::angular_error_rad(double disparity_px) const {
  const double angle = std::atan(disparity_px / params_.focal_px);
  return params_.verging_eye == hal::Eye::kRight ? angle : -angle;
}

double VergenceController::next_target_rad(double verging_target_rad, double dominant_pan_rad,
                                           const DisparityMeasurement& measurement) const {
  if (!measurement.valid || measurement.confidence < params_.min_confidence ||
      !std::isfinite(measurement.disparity_px)) {
    return verging_target_rad;
  }
  const double step = std::clamp(params_.gain * angular_error_rad(measurement.disparity_px),
                                 -params_.max_step_rad, params_.max_step_rad);
  const double target = verging_target_rad + step;
  // No divergence: the right eye's pan may not fall below the left eye's.
  return params_.verging_eye == hal::Eye::kRight ? std::max(target, dominant_pan_rad)
                                                 : std::min(target, dominant_pan_rad);
}

}  // namespace cambio::control
