// Motion on known translations between two frames of one eye.
#include "cambio/perception/motion_estimator.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>

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

TEST(Motion, KeyFlowIsTheDisplacementSinceTheKeyFrameUntilItIsRenewed) {
  RetinaConfig retina_config;
  MotionConfig config;
  config.rekey_shift_px = 3.0;
  config.rekey_frames = 100;
  MotionEstimator motion(config, 3.0, retina_config.levels, 16, 16);
  Retina retina(retina_config, motion.apron_px(), 640, 480);
  const testing::Texture texture(5);
  MotionResult result;
  // The scene moves 0.7 px right and 0.3 px up per frame.
  std::uint64_t key = 0;
  int renewals = 0;
  double key_x = 0.0, key_y = 0.0;  // Where the scene was at the key frame.
  for (int n = 0; n < 12; ++n) {
    const double x = 0.7 * n, y = -0.3 * n;
    ASSERT_EQ(retina.build(testing::render(texture, 640, 480, -x, -y), {320, 240}),
              hal::Status::kOk);
    motion.estimate(retina, result, nullptr);
    EXPECT_EQ(result.frame, static_cast<std::uint64_t>(n + 1));
    if (n == 0) {
      EXPECT_FALSE(result.key_valid);
      key = result.frame;
      continue;
    }
    ASSERT_TRUE(result.key_valid) << n;
    if (result.key_frame != key) {
      // A new key is the frame before the first that is measured from it.
      EXPECT_EQ(result.key_frame, result.frame - 1) << n;
      key = result.key_frame;
      key_x = 0.7 * (n - 1);
      key_y = -0.3 * (n - 1);
      ++renewals;
    }
    EXPECT_NEAR(result.key_flow_x_px, x - key_x, 0.1) << n;
    EXPECT_NEAR(result.key_flow_y_px, y - key_y, 0.1) << n;
    EXPECT_LE(std::hypot(result.key_flow_x_px, result.key_flow_y_px), 3.0 + 0.77) << n;
  }
  // 0.76 px a frame: a new key after every fourth frame's displacement exceeds 3 px.
  EXPECT_EQ(renewals, 2);
}

TEST(Motion, StripesMovingAlongThemselvesGiveTheAcrossComponentAndNoAlongMotion) {
  // Vertical stripes (period 40 px): only the x motion is observable (the aperture problem). The
  // y component keeps the prior (none) instead of whatever the noise of a singular system says.
  const auto stripes = [](double x, double) { return 128.0 + 60.0 * std::cos(x * 0.157); };
  const auto render = [&](double dx, double dy) {
    hal::Image image(640, 480, hal::PixelFormat::kGrey8);
    for (int y = 0; y < 480; ++y) {
      for (int x = 0; x < 640; ++x) {
        image.row(y)[x] = static_cast<std::uint8_t>(std::lround(stripes(x + dx, y + dy)));
      }
    }
    return image;
  };
  RetinaConfig retina_config;
  MotionEstimator motion(MotionConfig{}, 3.0, retina_config.levels, 16, 16);
  Retina retina(retina_config, motion.apron_px(), 640, 480);
  MotionResult result;
  ASSERT_EQ(retina.build(render(0.0, 0.0), {320, 240}), hal::Status::kOk);
  motion.estimate(retina, result, nullptr);
  ASSERT_EQ(retina.build(render(-1.2, -2.5), {320, 240}), hal::Status::kOk);
  motion.estimate(retina, result, nullptr);
  ASSERT_TRUE(result.valid);
  EXPECT_NEAR(result.flow_x_px, 1.2, 0.1);
  EXPECT_NEAR(result.flow_y_px, 0.0, 0.05);
}

}  // namespace
}  // namespace cambio::perception
