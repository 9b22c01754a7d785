// Motion on known translations between two frames of one eye.
#include "cambio/perception/motion_estimator.hpp"

#include <gtest/gtest.h>

#include "synthetic_images.hpp"

namespace cambio::perception {
namespace {

MotionResult track(double dx, double dy, int side, unsigned seed) {
  RetinaConfig retina_config;
  retina_config.width_px = side;
  retina_config.height_px = side;
  MotionConfig config;
  MotionEstimator motion(config, 3.0, retina_config.levels, side, side);
  Retina retina(retina_config, motion.apron_px(), 640, 480);
  const testing::Texture texture(seed);
  // The scene moves by (dx, dy): frame 2 at p shows what frame 1 showed at p - (dx, dy).
  const hal::Image first = testing::render(texture, 640, 480);
  const hal::Image second = testing::render(texture, 640, 480, -dx, -dy);
  MotionResult result;
  std::vector<float> temporal(static_cast<std::size_t>(4 * side * side));
  EXPECT_EQ(retina.build(first, {320, 240}), hal::Status::kOk);
  motion.estimate(retina, result, temporal.data());
  EXPECT_FALSE(result.valid);
  EXPECT_EQ(retina.build(second, {320, 240}), hal::Status::kOk);
  motion.estimate(retina, result, temporal.data());
  return result;
}

TEST(Motion, RecoversKnownTranslations) {
  const double cases[][2] = {{0.0, 0.0},  {0.5, 0.0},  {0.0, -0.75}, {1.5, 1.0},
                             {-3.0, 2.0}, {6.0, -4.0}, {11.0, 7.0}};
  for (const auto& c : cases) {
    for (const unsigned seed : {3u, 4u}) {
      const MotionResult result = track(c[0], c[1], 16, seed);
      ASSERT_TRUE(result.valid) << c[0] << "," << c[1];
      EXPECT_NEAR(result.flow_x_px, c[0], 0.1 + 0.02 * std::abs(c[0]))
          << c[0] << "," << c[1] << " level " << result.level;
      EXPECT_NEAR(result.flow_y_px, c[1], 0.1 + 0.02 * std::abs(c[1]))
          << c[0] << "," << c[1] << " level " << result.level;
    }
  }
}

TEST(Motion, TemporalDerivativeIsZeroForAStillSceneAndFlagsFixationChanges) {
  RetinaConfig retina_config;
  MotionEstimator motion(MotionConfig{}, 3.0, 4, 16, 16);
  Retina retina(retina_config, motion.apron_px(), 320, 240);
  const hal::Image image = testing::render(testing::Texture(6), 320, 240);
  std::vector<float> temporal(4 * 16 * 16, 1.0f);
  MotionResult result;
  ASSERT_EQ(retina.build(image, {160, 120}), hal::Status::kOk);
  motion.estimate(retina, result, temporal.data());
  ASSERT_EQ(retina.build(image, {160, 120}), hal::Status::kOk);
  motion.estimate(retina, result, temporal.data());
  for (const float v : temporal) ASSERT_EQ(v, 0.0f);
  EXPECT_TRUE(result.valid);
  EXPECT_NEAR(result.flow_x_px, 0.0f, 1e-3);
  ASSERT_EQ(retina.build(image, {150, 120}), hal::Status::kOk);
  motion.estimate(retina, result, temporal.data());
  EXPECT_TRUE(result.fixation_changed);
  EXPECT_FALSE(result.valid);
}

}  // namespace
}  // namespace cambio::perception
