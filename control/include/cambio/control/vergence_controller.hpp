#pragma once

#include "cambio/hal/eye.hpp"

namespace cambio::control {

/// The controller's settings. No tuning defaults here: they come from the experiment file
/// (config::GazeVergenceConfig holds the defaults for keys it leaves out, and apps/ copies them
/// in). The zeros below are refused by the controller, so a field left unset cannot pass.
struct VergenceParams {
  /// The other eye is dominant: it keeps its fixation point.
  hal::Eye verging_eye = hal::Eye::kRight;
  double focal_px = 0.0;  ///< Focal length of the verging eye (pixels).
  /// Fraction of the measured angular error corrected per new measurement (0, 1]. Below 1 the
  /// loop stays stable despite the camera-to-measurement dead time.
  double gain = 0.0;
  double min_confidence = 0.0;  ///< Measurements below this are ignored (untextured targets).
  double max_step_rad = 0.0;    ///< Largest correction per measurement (> 0).
};

/// One disparity measurement at the retina centres (level-0 pixels, x_left − x_right).
struct DisparityMeasurement {
  bool valid = false;
  double disparity_px = 0.0;
  double confidence = 0.0;
};

/// Verges one eye onto the point the dominant eye fixates by driving the disparity at the
/// retina centres to zero (the paper's vergence controller, Section 5).
///
/// Geometry (eye pan axes vertical, positive pan turns an eye to its left): with the left eye on
/// the point, the point sits disparity_px to the left of the right image's centre, so the right
/// eye turns left by atan(disparity / f); with the right eye dominant the left eye turns right
/// by the same angle. The eyes never diverge: right_pan >= left_pan (parallel at most).
/// Pure and allocation-free; real-time safe.
class VergenceController {
 public:
  explicit VergenceController(const VergenceParams& params);

  /// The verging eye's new pan target from its current target, the dominant eye's pan and a
  /// measurement. Invalid or low-confidence measurements leave the target unchanged.
  double next_target_rad(double verging_target_rad, double dominant_pan_rad,
                         const DisparityMeasurement& measurement) const;

  /// The angle the verging eye must still turn for a measurement (rad; sign as applied).
  double angular_error_rad(double disparity_px) const;

  const VergenceParams& params() const { return params_; }

 private:
  VergenceParams params_;
};

}  // namespace cambio::control
