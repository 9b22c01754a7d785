#include "stereo_test_pair.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <numbers>
#include <random>
#include <vector>

namespace cambio::app {

namespace {

/// The same pair as the cameras deliver it: rgb8 whose luma is the grey pair.
void to_rgb(const hal::Image& grey, hal::Image& rgb) {
  rgb.resize(grey.width_px, grey.height_px, hal::PixelFormat::kRgb8);
  for (std::size_t i = 0; i < grey.pixels.size(); ++i) {
    for (std::size_t c = 0; c < 3; ++c) rgb.pixels[3 * i + c] = grey.pixels[i];
  }
}

/// A pair of the given size whose left image is value(x, y) and right image value(x + d, y).
template <typename Value>
BenchStereoPair sample_pair(const Value& value) {
  BenchStereoPair pair;
  pair.left.resize(kBenchPairWidthPx, kBenchPairHeightPx, hal::PixelFormat::kGrey8);
  pair.right.resize(kBenchPairWidthPx, kBenchPairHeightPx, hal::PixelFormat::kGrey8);
  for (int y = 0; y < kBenchPairHeightPx; ++y) {
    for (int x = 0; x < kBenchPairWidthPx; ++x) {
      pair.left.row(y)[x] = value(x, y);
      pair.right.row(y)[x] = value(x + kBenchPairDisparityPx, y);
    }
  }
  to_rgb(pair.left, pair.left_rgb);
  to_rgb(pair.right, pair.right_rgb);
  return pair;
}

std::uint8_t to_grey(double v) {
  return static_cast<std::uint8_t>(std::clamp(std::lround(v), 0L, 255L));
}

struct Wave {
  double fx, fy, phase, amplitude;
};

/// 128 plus the waves at (x + dx, y), for every pixel of a bench-sized grey image. Each wave is
/// cos(a + b) = cos a cos b - sin a sin b with a from the column and b from the row: a cosine
/// and a sine per column and per row, not 48 cosines per pixel (0.4 s of every bench's start).
void wave_image(const std::vector<Wave>& waves, double dx, hal::Image& image) {
  constexpr auto kWidth = static_cast<std::size_t>(kBenchPairWidthPx);
  std::vector<double> sum(kWidth * kBenchPairHeightPx, 128.0);
  std::vector<double> cos_x(kWidth), sin_x(kWidth);
  for (const Wave& w : waves) {
    for (std::size_t x = 0; x < kWidth; ++x) {
      const double a = 2 * std::numbers::pi * w.fx * (static_cast<double>(x) + dx);
      cos_x[x] = w.amplitude * std::cos(a);
      sin_x[x] = w.amplitude * std::sin(a);
    }
    for (int y = 0; y < kBenchPairHeightPx; ++y) {
      const double b = 2 * std::numbers::pi * w.fy * y + w.phase;
      const double cos_y = std::cos(b);
      const double sin_y = std::sin(b);
      double* row = sum.data() + static_cast<std::size_t>(y) * kWidth;
      for (std::size_t x = 0; x < kWidth; ++x) row[x] += cos_x[x] * cos_y - sin_x[x] * sin_y;
    }
  }
  image.resize(kBenchPairWidthPx, kBenchPairHeightPx, hal::PixelFormat::kGrey8);
  for (int y = 0; y < kBenchPairHeightPx; ++y) {
    const double* row = sum.data() + static_cast<std::size_t>(y) * kWidth;
    for (std::size_t x = 0; x < kWidth; ++x) image.row(y)[x] = to_grey(row[x]);
  }
}

}  // namespace

BenchStereoPair make_bench_pair() {
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  std::vector<Wave> waves;
  for (int i = 0; i < 48; ++i) {
    const double f =
        std::exp(std::log(1.0 / 256) + (std::log(1.0 / 5) - std::log(1.0 / 256)) * unit(rng));
    const double angle = 2 * std::numbers::pi * unit(rng);
    waves.push_back({f * std::cos(angle), f * std::sin(angle), 2 * std::numbers::pi * unit(rng),
                     3.0 / std::sqrt(f) / 48.0 * 8.0});
  }
  BenchStereoPair pair;
  wave_image(waves, 0.0, pair.left);
  wave_image(waves, kBenchPairDisparityPx, pair.right);
  to_rgb(pair.left, pair.left_rgb);
  to_rgb(pair.right, pair.right_rgb);
  return pair;
}

BenchStereoPair make_horizontal_stripes_pair() {
  const auto value = [](double /*x*/, double y) {
    const double v = 128 + 40 * std::cos(2 * std::numbers::pi * y / 6.0) +
                     40 * std::cos(2 * std::numbers::pi * y / 17.0 + 1.0) +
                     30 * std::cos(2 * std::numbers::pi * y / 40.0 + 2.0);
    return to_grey(v);
  };
  return sample_pair(value);
}

}  // namespace cambio::app
