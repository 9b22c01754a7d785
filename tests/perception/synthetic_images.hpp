#pragma once
// Synthetic test images with known geometry: band-limited textures evaluated in closed form at
// any sub-pixel shift, and anti-aliased ellipses.

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <numbers>
#include <random>
#include <vector>

#include "cambio/hal/image.hpp"

namespace cambio::perception::testing {

/// A sum of cosines with random directions and phases, frequencies log-spaced from
/// 1/256 to 1/5 cycles per pixel (so every retina level sees texture), amplitudes falling as
/// f^-0.5. Evaluated exactly at real coordinates, so shifted copies are exact.
class Texture {
 public:
  explicit Texture(unsigned seed, double contrast = 40.0) {
    std::mt19937 rng(seed);
    std::uniform_real_distribution<double> unit(0.0, 1.0);
    const int count = 48;
    double total = 0.0;
    for (int i = 0; i < count; ++i) {
      Wave wave;
      const double f = std::exp(std::log(1.0 / 256.0) +
                                (std::log(1.0 / 5.0) - std::log(1.0 / 256.0)) * unit(rng));
      const double angle = 2.0 * std::numbers::pi * unit(rng);
      wave.fx = f * std::cos(angle);
      wave.fy = f * std::sin(angle);
      wave.phase = 2.0 * std::numbers::pi * unit(rng);
      wave.amplitude = 1.0 / std::sqrt(f);
      total += wave.amplitude;
      waves_.push_back(wave);
    }
    for (auto& wave : waves_) wave.amplitude *= 2.5 * contrast / total;
  }
  double operator()(double x, double y) const {
    double v = 128.0;
    for (const auto& w : waves_)
      v += w.amplitude * std::cos(2.0 * std::numbers::pi * (w.fx * x + w.fy * y) + w.phase);
    return v;
  }

  struct Wave {
    double fx, fy, phase, amplitude;
  };
  const std::vector<Wave>& waves() const { return waves_; }

 private:
  std::vector<Wave> waves_;
};

/// An image whose pixel (x, y) is texture(x + dx, y + dy), rounded and clamped to 8 bit.
/// Each wave is cos(a + b) = cos(a) cos(b) - sin(a) sin(b) with a = 2 pi fx (x + dx) and
/// b = 2 pi fy (y + dy) + phase: a cosine and a sine per column and per row instead of a cosine
/// per pixel (48 per pixel made rendering most of the perception tests' time, ~2 s a test).
inline hal::Image render(const Texture& texture, int width, int height, double dx = 0.0,
                         double dy = 0.0) {
  const auto w = static_cast<std::size_t>(width);
  std::vector<double> sum(w * static_cast<std::size_t>(height), 128.0);
  std::vector<double> cos_x(w), sin_x(w);
  for (const Texture::Wave& wave : texture.waves()) {
    for (std::size_t x = 0; x < w; ++x) {
      const double a = 2.0 * std::numbers::pi * wave.fx * (static_cast<double>(x) + dx);
      cos_x[x] = wave.amplitude * std::cos(a);
      sin_x[x] = wave.amplitude * std::sin(a);
    }
    for (int y = 0; y < height; ++y) {
      const double b = 2.0 * std::numbers::pi * wave.fy * (y + dy) + wave.phase;
      const double cos_y = std::cos(b);
      const double sin_y = std::sin(b);
      double* row = sum.data() + static_cast<std::size_t>(y) * w;
      for (std::size_t x = 0; x < w; ++x) row[x] += cos_x[x] * cos_y - sin_x[x] * sin_y;
    }
  }
  hal::Image image(width, height, hal::PixelFormat::kGrey8);
  for (int y = 0; y < height; ++y) {
    const double* row = sum.data() + static_cast<std::size_t>(y) * w;
    for (std::size_t x = 0; x < w; ++x) {
      image.row(y)[x] = static_cast<std::uint8_t>(std::clamp(std::lround(row[x]), 0L, 255L));
    }
  }
  return image;
}

/// A uniform grey image with optional Gaussian sensor noise.
inline hal::Image flat(int width, int height, double grey, double noise_sigma, unsigned seed) {
  hal::Image image(width, height, hal::PixelFormat::kGrey8);
  std::mt19937 rng(seed);
  std::normal_distribution<double> noise(0.0, noise_sigma > 0.0 ? noise_sigma : 1.0);
  for (auto& p : image.pixels) {
    const double v = grey + (noise_sigma > 0.0 ? noise(rng) : 0.0);
    p = static_cast<std::uint8_t>(std::clamp(std::lround(v), 0L, 255L));
  }
  return image;
}

/// A bright filled ellipse (semi-axes a >= b, major axis at `angle` from +x towards +y) on a dark
/// background, anti-aliased by 8 x 8 supersampling.
inline hal::Image ellipse(int width, int height, double cx, double cy, double a, double b,
                          double angle) {
  hal::Image image(width, height, hal::PixelFormat::kGrey8);
  const double c = std::cos(angle);
  const double s = std::sin(angle);
  for (int y = 0; y < height; ++y) {
    for (int x = 0; x < width; ++x) {
      int inside = 0;
      for (int j = 0; j < 8; ++j) {
        for (int i = 0; i < 8; ++i) {
          const double px = x - 0.5 + (i + 0.5) / 8.0 - cx;
          const double py = y - 0.5 + (j + 0.5) / 8.0 - cy;
          const double u = c * px + s * py;
          const double v = -s * px + c * py;
          inside += (u * u) / (a * a) + (v * v) / (b * b) <= 1.0 ? 1 : 0;
        }
      }
      image.row(y)[x] = static_cast<std::uint8_t>(20 + (220 * inside + 32) / 64);
    }
  }
  return image;
}

}  // namespace cambio::perception::testing
