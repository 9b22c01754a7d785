// Motion on known translations between two frames of one eye.
#include "cambio/perception/motion_estimator.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <numbers>

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

/// A pursued target seen by an eye following it: a checkered square (period `period_px`, side
/// `side_px`, a product of cosines) centred at (cx, cy) with its pattern moved by (dx, dy), over
/// `background` moved by (bx, by).
hal::Image checkered_target(const hal::Image& background, double cx, double cy, double side_px,
                            double period_px, double dx, double dy) {
  hal::Image image = background;
  const double k = 2.0 * std::numbers::pi / period_px;
  for (int y = 0; y < image.height_px; ++y) {
    for (int x = 0; x < image.width_px; ++x) {
      if (std::abs(x - cx) > side_px / 2 || std::abs(y - cy) > side_px / 2) continue;
      const double v = 128.0 + 90.0 * std::cos(k * (x - dx)) * std::cos(k * (y - dy));
      image.row(y)[x] = static_cast<std::uint8_t>(std::lround(v));
    }
  }
  return image;
}

TEST(Motion, OnAPeriodicTargetAValidKeyNeverJumpsItsContentByAPeriod) {
  // An eye pursuing a small checkered target: the target slips 1 px a frame on the retina,
  // jittering, while the background sweeps past at 4-6 px a frame. The coarser levels' windows
  // are mostly background, so a
  // frame's flow or the key's match may lock onto a neighbouring period of the checker. A
  // consumer placing the target by key_flow (pursuit) must not see it jump: a valid key differs
  // from where the frames' flows put its content by a small correction only.
  RetinaConfig retina_config;
  MotionConfig config;
  MotionEstimator motion(config, 3.0, retina_config.levels, 16, 16);
  Retina retina(retina_config, motion.apron_px(), 640, 480);
  const testing::Texture texture(9);
  MotionResult result;
  MotionResult before;
  double background_x = 0.0;
  int keyed = 0;
  for (int n = 0; n < 60; ++n) {
    background_x += 4.0 + 2.0 * std::abs(std::sin(0.7 * n));
    const double drift_x = 1.0 * n + 1.5 * std::sin(1.3 * n);  // The target, on the retina.
    const hal::Image background = testing::render(texture, 640, 480, background_x, 0.0);
    ASSERT_EQ(
        retina.build(checkered_target(background, 320, 240, 24, 7.0, drift_x, 0.0), {320, 240}),
        hal::Status::kOk);
    motion.estimate(retina, result, nullptr);
    if (result.key_valid && result.valid) {
      // Where the key's content was a frame ago (nowhere yet if the key is that frame), moved
      // by this frame's flow.
      const bool same_key = before.key_valid && before.key_frame == result.key_frame;
      const double sum_x = (same_key ? before.key_flow_x_px : 0.0) + result.flow_x_px;
      const double sum_y = (same_key ? before.key_flow_y_px : 0.0) + result.flow_y_px;
      EXPECT_LE(std::hypot(result.key_flow_x_px - sum_x, result.key_flow_y_px - sum_y),
                MotionEstimator::kMaxKeyCorrectionPx + 1e-3)
          << n;
      ++keyed;
    }
    before = result;
  }
  EXPECT_GT(keyed, 10) << "the key was hardly ever used";
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
  // Every level below the field sees the stripes only: the result says the flow is measured
  // along x (the stripes' gradient) and not across it.
  EXPECT_TRUE(result.one_directional);
  EXPECT_NEAR(std::abs(std::cos(result.gradient_orientation_rad)), 1.0, 1e-3);
}

TEST(Motion, ATexturedFoveaIsMeasuredBothWays) {
  for (const unsigned seed : {3u, 4u, 5u}) {
    const MotionResult result = track(1.5, -1.0, 16, seed);
    ASSERT_TRUE(result.valid);
    EXPECT_FALSE(result.one_directional) << "seed " << seed;
  }
}

TEST(Motion, APursuedTargetKeepsItsOwnMotionWhileTheBackgroundSweepsPast) {
  // Smooth pursuit as the fovea sees it: a textured disc (radius 24 px, wider than the two finest
  // levels' windows) nearly still at the fixation point, drifting 0.6 px right and 0.2 px down a
  // frame, while the background (a checker of 24 px squares) sweeps 12 px left a frame: the coarse
  // levels, mostly background, start the fine ones too far off for them to converge. Truth: the
  // disc's motion, every frame, at the fovea (level 0).
  const testing::Texture disc_texture(7);
  const auto render = [&](int n) {
    const double tx = 0.6 * n, ty = 0.2 * n, bx = -12.0 * n;
    hal::Image image(640, 480, hal::PixelFormat::kGrey8);
    for (int y = 0; y < 480; ++y) {
      for (int x = 0; x < 640; ++x) {
        const double u = x - 320.0 - tx, v = y - 240.0 - ty;
        const bool on_disc = u * u + v * v < 24.0 * 24.0;
        const bool light = (static_cast<int>(std::floor((x - bx) / 24.0)) +
                            static_cast<int>(std::floor(y / 24.0))) %
                               2 !=
                           0;
        const double grey = on_disc ? disc_texture(320.0 + u, 240.0 + v) : (light ? 190.0 : 60.0);
        image.row(y)[x] = static_cast<std::uint8_t>(std::clamp(std::lround(grey), 0L, 255L));
      }
    }
    return image;
  };
  RetinaConfig retina_config;
  MotionEstimator motion(MotionConfig{}, 3.0, retina_config.levels, 16, 16);
  Retina retina(retina_config, motion.apron_px(), 640, 480);
  MotionResult result;
  for (int n = 0; n < 10; ++n) {
    ASSERT_EQ(retina.build(render(n), {320, 240}), hal::Status::kOk);
    motion.estimate(retina, result, nullptr);
    if (n < 2) continue;  // The first flow comes coarse to fine, with nothing before it.
    ASSERT_TRUE(result.valid) << n;
    EXPECT_EQ(result.level, 0) << n;
    EXPECT_NEAR(result.flow_x_px, 0.6, 0.15) << n;
    EXPECT_NEAR(result.flow_y_px, 0.2, 0.15) << n;
  }
}

}  // namespace
}  // namespace cambio::perception
