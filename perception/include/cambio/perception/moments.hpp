#pragma once

#include "cambio/perception/perception_config.hpp"
#include "cambio/perception/retina.hpp"

namespace cambio::perception {

/// Statistical moments of a map region in source-image pixels (x right, y down).
struct Moments {
  bool valid = false;     ///< False when the region is empty.
  double area_px2 = 0.0;  ///< Zeroth moment: sum of weights times the block area.
  double centroid_x_px = 0.0;
  double centroid_y_px = 0.0;
  double mu20_px2 = 0.0;  ///< Central second moments normalised by the zeroth (a covariance).
  double mu02_px2 = 0.0;
  double mu11_px2 = 0.0;
  double orientation_rad = 0.0;  ///< Major axis from +x towards +y, in (-pi/2, pi/2].
  double eccentricity = 0.0;     ///< sqrt(1 - minor^2 / major^2): 0 for a disc, -> 1 for a line.
};

/// Moments of a width x height map (rows `stride` floats apart) whose samples lie on `level`'s
/// grid. Weights: kWeighted max(v - threshold, 0); kAbove 1 where v > threshold; kBelow 1 where
/// v < threshold. Real-time safe.
Moments compute_moments(const float* map, int stride, const RetinaLevelView& level,
                        MomentsConfig::Mode mode, double threshold) noexcept;

}  // namespace cambio::perception
