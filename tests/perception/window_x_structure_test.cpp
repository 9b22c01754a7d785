// The aperture test's measure against closed-form patterns: the share of gradient energy along
// x is sin^2 of the stripes' angle from horizontal (1 for vertical stripes, 0 for horizontal),
// and about one half for isotropic texture.
#include "cambio/perception/window_x_structure.hpp"

#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <numbers>
#include <vector>

#include "synthetic_images.hpp"

namespace cambio::perception {
namespace {

constexpr int kSize = 32;

/// One plane of kSize x kSize samples, value(x, y).
template <typename Value>
std::vector<float> plane(const Value& value) {
  std::vector<float> samples(kSize * kSize);
  for (int y = 0; y < kSize; ++y) {
    for (int x = 0; x < kSize; ++x) samples[y * kSize + x] = static_cast<float>(value(x, y));
  }
  return samples;
}

float x_structure(const std::vector<float>& samples) {
  const std::array<int, 1> features{0};
  return window_x_structure(samples.data(), kSize, kSize / 2, kSize / 2, kSize, 8, 8, features);
}

TEST(WindowXStructure, IsTheSquaredSineOfTheStripesAngleFromHorizontal) {
  for (const double angle_deg : {0.0, 10.0, 30.0, 45.0, 60.0, 90.0}) {
    const double a = angle_deg * std::numbers::pi / 180.0;
    // Stripes whose bars run at `a` from horizontal: the value varies along their normal.
    const auto samples = plane([&](int x, int y) {
      return std::sin(2.0 * std::numbers::pi * (-std::sin(a) * x + std::cos(a) * y) / 11.0);
    });
    const double expected = std::sin(a) * std::sin(a);
    // Central differences of a sampled sine: the share holds to a few hundredths.
    EXPECT_NEAR(x_structure(samples), expected, 0.03) << angle_deg << " deg";
  }
}

TEST(WindowXStructure, IsAboutAHalfForIsotropicTextureAndForNoGradientAtAll) {
  const testing::Texture texture(5);
  EXPECT_NEAR(x_structure(plane([&](int x, int y) { return texture(x, y); })), 0.5, 0.15);
  EXPECT_FLOAT_EQ(x_structure(plane([](int, int) { return 3.0; })), 0.5f);
}

TEST(WindowXStructure, DoesNotDependOnContrastOrOffset) {
  const testing::Texture texture(6);
  const float unit = x_structure(plane([&](int x, int y) { return texture(x, y); }));
  const float scaled = x_structure(plane([&](int x, int y) { return 7.0 * texture(x, y) - 40.0; }));
  EXPECT_NEAR(unit, scaled, 1e-4);
}

}  // namespace
}  // namespace cambio::perception
