#pragma once

#include <cstddef>
#include <span>

namespace cambio::perception {

/// The share of a window's feature gradient energy that runs along x, in [0, 1]: about 0.5 for
/// isotropic texture, 1 for vertical stripes, near 0 for horizontal ones. A horizontal shift is
/// measurable only where the features vary along x (the aperture problem): a window whose
/// share is small scores every shift alike, and its best shift is noise. The share is a ratio,
/// so it does not depend on the texture's contrast or the features' units. Central differences
/// inside the (2 half_x + 1) x (2 half_y + 1) window centred at (centre_x, centre_y) of planes
/// `width` x `height`; 0.5 (no preference) for a window without gradients.
inline float window_x_structure(const float* maps, int width, int centre_x, int centre_y,
                                int height, int half_x, int half_y,
                                std::span<const int> features) noexcept {
  double along_x = 0.0;
  double along_y = 0.0;
  for (const int f : features) {
    const float* plane = maps + static_cast<std::ptrdiff_t>(f) * width * height;
    for (int y = centre_y - half_y + 1; y < centre_y + half_y; ++y) {
      const float* row = plane + y * width;
      for (int x = centre_x - half_x + 1; x < centre_x + half_x; ++x) {
        const double gx = row[x + 1] - row[x - 1];
        const double gy = row[x + width] - row[x - width];
        along_x += gx * gx;
        along_y += gy * gy;
      }
    }
  }
  const double total = along_x + along_y;
  return total > 0.0 ? static_cast<float>(along_x / total) : 0.5f;
}

}  // namespace cambio::perception
