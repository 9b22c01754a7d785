#pragma once

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <span>

namespace cambio::perception {

/// Zero-mean normalised cross-correlation of two windows of (2 half_x + 1) x (2 half_y + 1)
/// samples, summed over the feature planes (the disparity search's score): the left window
/// centred at column `left_x` of planes `left_width` wide, the right at `right_x` of planes
/// `right_width` wide, both at row `centre_y` of planes `height` tall.
inline float window_zncc(const float* left_maps, int left_width, int left_x,
                         const float* right_maps, int right_width, int right_x, int centre_y,
                         int height, int half_x, int half_y,
                         std::span<const int> features) noexcept {
  const int w = 2 * half_x + 1;
  const int n = w * (2 * half_y + 1);
  double cross = 0.0, left_energy = 0.0, right_energy = 0.0;
  for (const int f : features) {
    const float* l = left_maps + static_cast<std::ptrdiff_t>(f) * left_width * height;
    const float* r = right_maps + static_cast<std::ptrdiff_t>(f) * right_width * height;
    float sl = 0.0f, sr = 0.0f, sll = 0.0f, srr = 0.0f, slr = 0.0f;
    for (int y = centre_y - half_y; y <= centre_y + half_y; ++y) {
      const float* lr = l + y * left_width + left_x - half_x;
      const float* rr = r + y * right_width + right_x - half_x;
      for (int x = 0; x < w; ++x) {
        sl += lr[x];
        sr += rr[x];
        sll += lr[x] * lr[x];
        srr += rr[x] * rr[x];
        slr += lr[x] * rr[x];
      }
    }
    cross += static_cast<double>(slr) - static_cast<double>(sl) * sr / n;
    left_energy += static_cast<double>(sll) - static_cast<double>(sl) * sl / n;
    right_energy += static_cast<double>(srr) - static_cast<double>(sr) * sr / n;
  }
  const double denominator = std::sqrt(std::max(left_energy, 0.0) * std::max(right_energy, 0.0));
  return denominator > 0.0 ? static_cast<float>(cross / denominator) : 0.0f;
}

}  // namespace cambio::perception
