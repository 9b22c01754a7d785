#include "cambio/perception/moments.hpp"

#include <algorithm>
#include <cmath>

namespace cambio::perception {

Moments compute_moments(const float* map, int stride, const RetinaLevelView& level,
                        MomentsConfig::Mode mode, double threshold) noexcept {
  // Accumulate in level coordinates about the map centre (keeps the sums well conditioned).
  const double cx = 0.5 * (level.width - 1);
  const double cy = 0.5 * (level.height - 1);
  double m00 = 0.0, m10 = 0.0, m01 = 0.0, m20 = 0.0, m02 = 0.0, m11 = 0.0;
  for (int y = 0; y < level.height; ++y) {
    for (int x = 0; x < level.width; ++x) {
      const double v = map[y * stride + x];
      double w = 0.0;
      switch (mode) {
        case MomentsConfig::Mode::kWeighted:
          w = std::max(v - threshold, 0.0);
          break;
        case MomentsConfig::Mode::kAbove:
          w = v > threshold ? 1.0 : 0.0;
          break;
        case MomentsConfig::Mode::kBelow:
          w = v < threshold ? 1.0 : 0.0;
          break;
      }
      const double dx = x - cx;
      const double dy = y - cy;
      m00 += w;
      m10 += w * dx;
      m01 += w * dy;
      m20 += w * dx * dx;
      m02 += w * dy * dy;
      m11 += w * dx * dy;
    }
  }
  Moments result;
  if (m00 <= 0.0) return result;
  const double scale = level.scale_px;
  const double mean_x = m10 / m00;
  const double mean_y = m01 / m00;
  result.valid = true;
  result.area_px2 = m00 * scale * scale;
  result.centroid_x_px = level.to_source_x(cx + mean_x);
  result.centroid_y_px = level.to_source_y(cy + mean_y);
  result.mu20_px2 = (m20 / m00 - mean_x * mean_x) * scale * scale;
  result.mu02_px2 = (m02 / m00 - mean_y * mean_y) * scale * scale;
  result.mu11_px2 = (m11 / m00 - mean_x * mean_y) * scale * scale;
  result.orientation_rad =
      0.5 * std::atan2(2.0 * result.mu11_px2, result.mu20_px2 - result.mu02_px2);
  const double half_trace = 0.5 * (result.mu20_px2 + result.mu02_px2);
  const double spread = std::hypot(0.5 * (result.mu20_px2 - result.mu02_px2), result.mu11_px2);
  const double major = half_trace + spread;
  const double minor = std::max(half_trace - spread, 0.0);
  result.eccentricity = major > 0.0 ? std::sqrt(std::max(0.0, 1.0 - minor / major)) : 0.0;
  return result;
}

}  // namespace cambio::perception
