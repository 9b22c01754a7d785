// Moments on an analytic ellipse: centroid, orientation, eccentricity and area are known.
#include "cambio/perception/moments.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "synthetic_images.hpp"

namespace cambio::perception {
namespace {

TEST(Moments, EllipseCentroidOrientationEccentricityAndArea) {
  const double a = 14.0;
  const double b = 6.0;
  for (const double angle_deg : {0.0, 30.0, -50.0, 75.0}) {
    const double angle = angle_deg * std::numbers::pi / 180.0;
    const double cx = 203.3;
    const double cy = 151.6;
    const hal::Image image = testing::ellipse(400, 300, cx, cy, a, b, angle);
    RetinaConfig config;
    config.levels = 2;
    config.width_px = 64;
    config.height_px = 64;
    Retina retina(config, 0, 400, 300);
    ASSERT_EQ(retina.build(image, {200, 150}), hal::Status::kOk);
    const RetinaLevelView level = retina.level(0);
    // Weighted by brightness above the background: each pixel weighs its covered fraction.
    const Moments m =
        compute_moments(level.interior, level.stride, level, MomentsConfig::Mode::kWeighted, 20.0);
    ASSERT_TRUE(m.valid);
    EXPECT_NEAR(m.centroid_x_px, cx, 0.02) << angle_deg;
    EXPECT_NEAR(m.centroid_y_px, cy, 0.02) << angle_deg;
    EXPECT_NEAR(std::remainder(m.orientation_rad - angle, std::numbers::pi), 0.0, 0.01)
        << angle_deg;
    EXPECT_NEAR(m.eccentricity, std::sqrt(1 - b * b / (a * a)), 0.005) << angle_deg;
    EXPECT_NEAR(m.area_px2 / 220.0, std::numbers::pi * a * b, 0.01 * std::numbers::pi * a * b);
    // The covariance of a uniform ellipse: a^2/4 along the major axis, b^2/4 across. Edge
    // pixels count their coverage at their centre, which adds up to 1/12 px^2 per axis.
    EXPECT_NEAR(m.mu20_px2 + m.mu02_px2, (a * a + b * b) / 4, 1.0 / 6.0 + 0.03) << angle_deg;
    // A coarser level sees the same shape from 2x2 blocks.
    const Moments coarse = compute_moments(retina.level(1).interior, retina.level(1).stride,
                                           retina.level(1), MomentsConfig::Mode::kWeighted, 20.0);
    EXPECT_NEAR(coarse.centroid_x_px, cx, 0.05);
    EXPECT_NEAR(coarse.centroid_y_px, cy, 0.05);
  }
}

TEST(Moments, ThresholdedRegionAndEmptyRegion) {
  const hal::Image image = testing::ellipse(200, 200, 100, 100, 10, 10, 0);
  RetinaConfig config;
  config.levels = 1;
  config.width_px = 48;
  config.height_px = 48;
  Retina retina(config, 0, 200, 200);
  ASSERT_EQ(retina.build(image, {100, 100}), hal::Status::kOk);
  const RetinaLevelView level = retina.level(0);
  const Moments disc =
      compute_moments(level.interior, level.stride, level, MomentsConfig::Mode::kAbove, 128);
  ASSERT_TRUE(disc.valid);
  EXPECT_NEAR(disc.area_px2, std::numbers::pi * 100, 8);
  EXPECT_LT(disc.eccentricity, 0.2);
  const Moments none =
      compute_moments(level.interior, level.stride, level, MomentsConfig::Mode::kAbove, 250);
  EXPECT_FALSE(none.valid);
}

}  // namespace
}  // namespace cambio::perception
