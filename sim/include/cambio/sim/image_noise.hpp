#pragma once

#include <cstdint>
#include <span>
#include <vector>

namespace cambio::sim {

/// Additive Gaussian image noise, seeded. Drawing a normal variate per pixel would cost more
/// than the render itself, so a table of 65,536 N(0, std) samples is built once and each pixel
/// adds an entry picked by a xorshift generator: the per-pixel distribution is the configured
/// Gaussian (to the table's resolution) and the sequence is reproducible for a seed.
class ImageNoise {
 public:
  /// Allocates the table. std == 0 makes apply() a no-op.
  ImageNoise(double std_grey_levels, std::uint64_t seed);
  double std_grey_levels() const { return std_; }
  /// Adds noise to every byte, saturating at 0 and 255. Real-time safe.
  void apply(std::span<std::uint8_t> pixels) noexcept;

 private:
  double std_ = 0.0;
  std::uint64_t state_ = 0;
  std::vector<float> table_;
};

}  // namespace cambio::sim
