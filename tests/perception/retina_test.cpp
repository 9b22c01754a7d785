// Retina levels against direct block averaging of the source pixels.
#include "cambio/perception/retina.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <string>

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

// Every sample of `level`, apron included, against the mean of its block computed here from the
// source pixels (edge pixels replicated), and its fraction_inside against a count of the
// footprint's pixels that lie in the image.
void expect_level_is_block_means(const RetinaLevelView& level, const hal::Image& image,
                                 const char* what) {
  const int b = level.scale_px;
  const int a = level.apron;
  for (int y = -a; y < level.height + a; ++y) {
    for (int x = -a; x < level.width + a; ++x) {
      const double expected =
          block_mean(image, level.origin_x_px + x * b, level.origin_y_px + y * b, b);
      // The block sums are exact integers below 2^24; the float mean differs by rounding only.
      ASSERT_NEAR(level.at(x, y), expected, 1e-4)
          << what << ": scale " << b << " at " << x << "," << y;
    }
  }
  const auto inside = [b, a](int origin, int samples, int size) {
    int count = 0;
    for (int p = origin - a * b; p < origin + (samples + a) * b; ++p) count += p >= 0 && p < size;
    return count;
  };
  const double footprint = static_cast<double>((level.width + 2 * a) * b) *
                           static_cast<double>((level.height + 2 * a) * b);
  EXPECT_NEAR(level.fraction_inside,
              inside(level.origin_x_px, level.width, image.width_px) *
                  static_cast<double>(inside(level.origin_y_px, level.height, image.height_px)) /
                  footprint,
              1e-6)
      << what;
}

// The paper's retina, its last level covering the field: with the apron, that level reaches
// past every edge of the image, and with the fixation off centre or outside the image its blocks
// widen further; every sample is still the replicate-border block mean.
TEST(Retina, FieldCoveringLevelIsTheBlockMeanAlsoPastEveryEdge) {
  struct Case {
    int width, height;
    PixelPoint fixation;
    int apron;
  };
  for (const Case c : {Case{640, 480, {320, 240}, 12}, Case{640, 480, {100, 400}, 12},
                       Case{640, 480, {0, 0}, 12}, Case{640, 480, {639, 479}, 3},
                       Case{203, 151, {5, 140}, 12}, Case{203, 151, {101, 75}, 0}}) {
    const hal::Image image = testing::render(testing::Texture(11), c.width, c.height);
    RetinaConfig config;  // 4 x 16 x 16
    config.coarsest_covers_field = true;
    Retina retina(config, c.apron, c.width, c.height);
    ASSERT_EQ(retina.build(image, c.fixation), hal::Status::kOk);
    const std::string what = std::to_string(c.width) + "x" + std::to_string(c.height) +
                             " fixation " + std::to_string(c.fixation.x) + "," +
                             std::to_string(c.fixation.y) + " apron " + std::to_string(c.apron);
    for (int k = 0; k < retina.levels(); ++k) {
      const RetinaLevelView level = retina.level(k);
      expect_level_is_block_means(level, image, (what + " level " + std::to_string(k)).c_str());
    }
    const RetinaLevelView coarse = retina.level(3);
    EXPECT_LE(coarse.origin_x_px, 0) << what;
    EXPECT_GE(coarse.origin_x_px + 16 * coarse.scale_px, c.width) << what;
    EXPECT_LE(coarse.origin_y_px, 0) << what;
    EXPECT_GE(coarse.origin_y_px + 16 * coarse.scale_px, c.height) << what;
  }
}

// A level may lie wholly beyond an edge (fixation far outside): every sample is an edge pixel's
// block mean and nothing of the image is inside.
TEST(Retina, LevelWhollyOutsideTheImageReplicatesTheEdge) {
  const hal::Image image = testing::render(testing::Texture(13), 120, 90);
  RetinaConfig config;
  config.levels = 2;
  Retina retina(config, 4, 120, 90);
  for (const PixelPoint f : {PixelPoint{-200, 45}, PixelPoint{60, 400}, PixelPoint{500, -300}}) {
    ASSERT_EQ(retina.build(image, f), hal::Status::kOk);
    for (int k = 0; k < retina.levels(); ++k) {
      expect_level_is_block_means(retina.level(k), image, "outside");
    }
    EXPECT_FLOAT_EQ(retina.level(0).fraction_inside, 0.0f);
  }
}

// An rgb8 image with independent textures in its three channels.
hal::Image colour_image(int width, int height) {
  const hal::Image r = testing::render(testing::Texture(21, 60.0), width, height);
  const hal::Image g = testing::render(testing::Texture(22, 60.0), width, height);
  const hal::Image b = testing::render(testing::Texture(23, 60.0), width, height);
  hal::Image image(width, height, hal::PixelFormat::kRgb8);
  for (int y = 0; y < height; ++y) {
    for (int x = 0; x < width; ++x) {
      std::uint8_t* p = image.row(y) + 3 * x;
      p[0] = r.row(y)[x];
      p[1] = g.row(y)[x];
      p[2] = b.row(y)[x];
    }
  }
  return image;
}

// Colour frames against converting the whole frame to grey with hal::luma_bt601 first and
// building the retina from that. The colour path converts each pixel it reads with the same
// function, so the sums are the same integers: tolerance 0.
TEST(Retina, ColourFramesGiveTheLevelsOfTheirGreyConversion) {
  const hal::Image colour = colour_image(320, 240);
  hal::Image grey(320, 240, hal::PixelFormat::kGrey8);
  for (int y = 0; y < 240; ++y) {
    for (int x = 0; x < 320; ++x) {
      const std::uint8_t* p = colour.row(y) + 3 * x;
      grey.row(y)[x] = hal::luma_bt601(p[0], p[1], p[2]);
    }
  }
  for (const bool covers : {false, true}) {
    RetinaConfig config;
    config.coarsest_covers_field = covers;
    Retina from_colour(config, 12, 320, 240);
    Retina from_grey(config, 12, 320, 240);
    for (const PixelPoint f : {PixelPoint{160, 120}, PixelPoint{7, 230}, PixelPoint{330, -4}}) {
      ASSERT_EQ(from_colour.build(colour, f), hal::Status::kOk);
      ASSERT_EQ(from_grey.build(grey, f), hal::Status::kOk);
      for (int k = 0; k < config.levels; ++k) {
        const RetinaLevelView c = from_colour.level(k);
        const RetinaLevelView g = from_grey.level(k);
        ASSERT_EQ(c.scale_px, g.scale_px);
        EXPECT_EQ(c.fraction_inside, g.fraction_inside);
        for (int y = -c.apron; y < c.height + c.apron; ++y) {
          for (int x = -c.apron; x < c.width + c.apron; ++x) {
            ASSERT_EQ(c.at(x, y), g.at(x, y))
                << "covers " << covers << " level " << k << " at " << x << "," << y;
          }
        }
      }
    }
  }
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
