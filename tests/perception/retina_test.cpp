// Retina levels against direct block averaging of the source pixels.
#include "cambio/perception/retina.hpp"

#include <gtest/gtest.h>

#include <algorithm>

#include "cambio/hal/luma.hpp"
#include "synthetic_images.hpp"

namespace cambio::perception {
namespace {

// Mean of the b x b block whose top-left source pixel is (x0, y0), edge pixels replicated.
double block_mean(const hal::Image& image, int x0, int y0, int b) {
  double sum = 0;
  for (int y = y0; y < y0 + b; ++y) {
    for (int x = x0; x < x0 + b; ++x) {
      const int cx = std::clamp(x, 0, image.width_px - 1);
      const int cy = std::clamp(y, 0, image.height_px - 1);
      const std::uint8_t* p = image.row(cy) + cx * image.channels();
      sum += image.channels() == 1 ? p[0] : hal::luma_bt601(p[0], p[1], p[2]);
    }
  }
  return sum / (b * b);
}

void expect_levels_are_block_means(const Retina& retina, const hal::Image& image, PixelPoint f) {
  for (int k = 0; k < retina.levels(); ++k) {
    const RetinaLevelView level = retina.level(k);
    const int b = 1 << k;
    ASSERT_EQ(level.scale_px, b);
    EXPECT_EQ(level.origin_x_px, f.x - (retina.width() / 2) * b);
    EXPECT_EQ(level.origin_y_px, f.y - (retina.height() / 2) * b);
    const int a = retina.apron();
    for (int y = -a; y < retina.height() + a; ++y) {
      for (int x = -a; x < retina.width() + a; ++x) {
        const double expected = block_mean(image, f.x + (x - retina.width() / 2) * b,
                                           f.y + (y - retina.height() / 2) * b, b);
        ASSERT_NEAR(level.at(x, y), expected, 1e-4) << "level " << k << " at " << x << "," << y;
      }
    }
  }
}

TEST(Retina, LevelsAreBlockAveragesAroundTheFixationIncludingTheApron) {
  const hal::Image image = testing::render(testing::Texture(3), 640, 480);
  RetinaConfig config;  // 4 x 16 x 16
  Retina retina(config, 12, 640, 480);
  const PixelPoint fixation{300, 200};
  ASSERT_EQ(retina.build(image, fixation), hal::Status::kOk);
  expect_levels_are_block_means(retina, image, fixation);
  EXPECT_FLOAT_EQ(retina.level(3).fraction_inside, 1.0f);
  // Level 0's centre sample is the fixation pixel itself.
  EXPECT_FLOAT_EQ(retina.level(0).at(8, 8), image.row(200)[300]);
}

TEST(Retina, OddSizesAndLargeLevels) {
  const hal::Image image = testing::render(testing::Texture(5), 320, 240);
  RetinaConfig config;
  config.levels = 3;
  config.width_px = 21;
  config.height_px = 9;
  Retina retina(config, 4, 320, 240);
  ASSERT_EQ(retina.build(image, {160, 120}), hal::Status::kOk);
  expect_levels_are_block_means(retina, image, {160, 120});
}

TEST(Retina, BorderReplicatesEdgePixelsAndReportsTheRealFraction) {
  const hal::Image image = testing::render(testing::Texture(7), 200, 150);
  RetinaConfig config;
  Retina retina(config, 12, 200, 150);
  for (const PixelPoint f : {PixelPoint{0, 0}, PixelPoint{199, 149}, PixelPoint{-30, 70}}) {
    ASSERT_EQ(retina.build(image, f), hal::Status::kOk);
    expect_levels_are_block_means(retina, image, f);
    EXPECT_LT(retina.level(0).fraction_inside, 1.0f);
  }
  ASSERT_EQ(retina.build(image, {0, 0}), hal::Status::kOk);
  // Level 0 spans 40 x 40 source px with its apron; a quarter of it lies in the image.
  EXPECT_NEAR(retina.level(0).fraction_inside, 0.25f, 1e-6);
}

TEST(Retina, ColourImagesUseLuma) {
  hal::Image image(64, 48, hal::PixelFormat::kRgb8);
  for (std::size_t i = 0; i < image.pixels.size(); ++i)
    image.pixels[i] = static_cast<std::uint8_t>((i * 37) % 251);
  RetinaConfig config;
  config.levels = 2;
  config.width_px = 8;
  config.height_px = 8;
  Retina retina(config, 2, 64, 48);
  ASSERT_EQ(retina.build(image, {30, 20}), hal::Status::kOk);
  expect_levels_are_block_means(retina, image, {30, 20});
}

TEST(Retina, CoarsestLevelCanCoverTheWholeField) {
  const hal::Image image = testing::render(testing::Texture(9), 640, 480);
  RetinaConfig config;
  config.coarsest_covers_field = true;
  Retina retina(config, 12, 640, 480);
  ASSERT_EQ(retina.build(image, {320, 240}), hal::Status::kOk);
  const RetinaLevelView coarse = retina.level(3);
  EXPECT_EQ(coarse.scale_px, 40);  // 16 blocks of 40 px span 640 px
  EXPECT_LE(coarse.origin_x_px, 0);
  EXPECT_GE(coarse.origin_x_px + 16 * coarse.scale_px, 640);
  EXPECT_LE(coarse.origin_y_px, 0);
  EXPECT_GE(coarse.origin_y_px + 16 * coarse.scale_px, 480);
  EXPECT_NEAR(coarse.at(3, 5),
              block_mean(image, coarse.origin_x_px + 3 * 40, coarse.origin_y_px + 5 * 40, 40),
              1e-3);
  EXPECT_EQ(retina.level(2).scale_px, 4);
}

TEST(Retina, CoordinateMappingRoundTrips) {
  const hal::Image image = testing::render(testing::Texture(1), 128, 128);
  Retina retina(RetinaConfig{}, 0, 128, 128);
  ASSERT_EQ(retina.build(image, {64, 64}), hal::Status::kOk);
  for (int k = 0; k < 4; ++k) {
    const RetinaLevelView level = retina.level(k);
    EXPECT_DOUBLE_EQ(level.to_level_x(level.to_source_x(3.25)), 3.25);
    // Block 8's source pixels are [64, 64 + b): its centre is 64 + (b - 1) / 2.
    EXPECT_DOUBLE_EQ(level.to_source_x(8), 64 + (level.scale_px - 1) / 2.0);
  }
}

TEST(Retina, RejectsEmptyImagesAndBadSizes) {
  Retina retina(RetinaConfig{}, 4, 64, 64);
  EXPECT_EQ(retina.build(hal::Image{}, {0, 0}), hal::Status::kRejected);
  RetinaConfig bad;
  bad.levels = 9;
  EXPECT_THROW(Retina(bad, 0, 64, 64), std::invalid_argument);
}

}  // namespace
}  // namespace cambio::perception
