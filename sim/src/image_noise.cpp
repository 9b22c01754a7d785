#include "cambio/sim/image_noise.hpp"

#include <algorithm>
#include <cmath>
#include <random>

namespace cambio::sim {

namespace {
constexpr std::size_t kTableSize = 1u << 16;
}

ImageNoise::ImageNoise(double std_grey_levels, std::uint64_t seed)
    : std_(std_grey_levels), state_(seed * 0x9E3779B97F4A7C15ULL | 1u) {
  if (std_ <= 0.0) return;
  std::mt19937_64 rng(seed);
  std::normal_distribution<float> normal(0.0f, static_cast<float>(std_));
  table_.resize(kTableSize);
  for (auto& value : table_) value = normal(rng);
}

void ImageNoise::apply(std::span<std::uint8_t> pixels) noexcept {
  if (table_.empty()) return;
  for (auto& pixel : pixels) {
    // xorshift64*; the top 16 bits index the table.
    state_ ^= state_ >> 12;
    state_ ^= state_ << 25;
    state_ ^= state_ >> 27;
    const std::uint64_t r = state_ * 0x2545F4914F6CDD1DULL;
    const float value = static_cast<float>(pixel) + table_[r >> 48] + 0.5f;
    pixel = static_cast<std::uint8_t>(std::clamp(value, 0.0f, 255.0f));
  }
}

}  // namespace cambio::sim
