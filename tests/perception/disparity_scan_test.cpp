// The whole-range scan against layered stereo pairs with known disparities: a textured square
// (the fixated object) in front of a differently textured background. The square's disparity is
// the truth (right(x) = left-world(x + d)); the background's is another, so a search that
// matches the background (a wide coarse window) gives a confident wrong answer.
#include "cambio/perception/disparity_scan.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "cambio/perception/sensory_servo.hpp"
#include "cambio/runtime/allocation_counter.hpp"
#include "synthetic_images.hpp"

namespace cambio::perception {
namespace {

constexpr int kWidth = 640;
constexpr int kHeight = 480;

/// The paper's retina (4 x 16 x 16, coarsest level over the field) with the scan over the
/// shipped head's range (f b / 0.3 m = 554 x 0.12 / 0.3 = 222 px).
SsmConfig paper_config_with_scan() {
  SsmConfig config;
  config.retina.coarsest_covers_field = true;
  config.disparity.search_range_px = 96;
  config.disparity.scan_range_px = largest_disparity_px(554.256, 0.12);
  config.motion.enabled = false;
  config.moments.enabled = false;
  return config;
}

/// The square of half-size `half_px` at the image centre, at disparity `object_d`, over a
/// background at `background_d`; pixel value from `value(x_world, y_world, layer)`. The right
/// eye's rows are `right_dy` px lower in the world (vertical disparity, as off the eyes' plane).
template <typename Value>
std::pair<hal::Image, hal::Image> layered_pair(double object_d, double background_d, int half_px,
                                               const Value& value, int right_dy = 0) {
  hal::Image left(kWidth, kHeight, hal::PixelFormat::kGrey8);
  hal::Image right(kWidth, kHeight, hal::PixelFormat::kGrey8);
  const auto in_square = [&](double x, int y) {
    return std::abs(x - kWidth / 2) <= half_px && std::abs(y - kHeight / 2) <= half_px;
  };
  for (int y = 0; y < kHeight; ++y) {
    for (int x = 0; x < kWidth; ++x) {
      const auto grey = [](double v) {
        return static_cast<std::uint8_t>(std::clamp(std::lround(v), 0L, 255L));
      };
      left.row(y)[x] = grey(in_square(x, y) ? value(x, y, 1) : value(x, y, 0));
      // The right eye sees the scene point of left column x + d at column x.
      const double object_x = x + object_d;
      const int world_y = y + right_dy;
      right.row(y)[x] = grey(in_square(object_x, world_y) ? value(object_x, world_y, 1)
                                                          : value(x + background_d, world_y, 0));
    }
  }
  return {std::move(left), std::move(right)};
}

DisparityResult run(const SsmConfig& config, const hal::Image& left, const hal::Image& right) {
  SensoryServo servo(config, left.width_px, left.height_px);
  SsmFrame frame = servo.make_frame();
  FeatureRequest request;
  request.maps = 0;
  EXPECT_EQ(servo.process(left, right, {kWidth / 2, kHeight / 2}, {kWidth / 2, kHeight / 2},
                          request, frame),
            hal::Status::kOk);
  return frame.summary.disparity;
}

TEST(DisparityScan, FindsTheFixatedObjectsDisparityAnywhereInTheRigsRange) {
  // Near objects give disparities the coarse-to-fine search alone cannot reach or trust; the
  // background sits at another disparity in every case.
  for (const auto& [object_d, background_d] :
       {std::pair{150.0, 12.0}, {-120.0, 5.0}, {205.0, 30.0}, {64.5, -8.0}, {3.0, 90.0}}) {
    const testing::Texture object(7);
    const testing::Texture background(8);
    const auto [left, right] = layered_pair(
        object_d, background_d, 80,
        [&](double x, int y, int l) { return l == 1 ? object(x, y) : background(x, y); });
    const DisparityResult result = run(paper_config_with_scan(), left, right);
    ASSERT_TRUE(result.valid) << object_d;
    EXPECT_NEAR(result.disparity_px, object_d, 0.5) << "background at " << background_d;
    EXPECT_GT(result.confidence, 0.5f) << object_d;
    EXPECT_GT(result.candidates, 0) << object_d;
  }
}

TEST(DisparityScan, AnObjectTooSmoothForTheFinerLevelsIsMeasuredBetweenTheScansBlocks) {
  // Blobs tens of pixels wide: the fovea's 9-px windows see no texture, so the estimate is the
  // scan level's (4-px blocks); its peak must be placed between blocks, not on the nearest.
  const auto value = [](double x, int y, int l) {
    const double u = x / 23.0;
    const double v = y / 29.0;
    return l == 1 ? 128.0 + 45.0 * std::sin(u) * std::cos(v) + 30.0 * std::cos(0.7 * u + 1.3 * v)
                  : 128.0 + 30.0 * std::sin(x / 9.0 + y / 13.0);
  };
  for (const double object_d : {13.0, 26.5, -30.0, 41.75}) {
    const auto [left, right] = layered_pair(object_d, 4.0, 100, value);
    const DisparityResult result = run(paper_config_with_scan(), left, right);
    ASSERT_TRUE(result.valid) << object_d;
    // The premise: no level finer than the scan's refined it.
    ASSERT_GE(result.level, 1) << object_d;
    EXPECT_NEAR(result.disparity_px, object_d, 1.0) << object_d << " from level " << result.level;
  }
}

TEST(DisparityScan, APeriodicTextureIsNotTrusted) {
  // Vertical stripes of a 24-px period: every 24 px of disparity matches alike, so the scan's
  // hypotheses tie and the confidence must say so, whatever disparity it reports.
  const auto [left, right] = layered_pair(60.0, 10.0, 120, [](double x, int, int l) {
    return l == 1 ? 128.0 + 60.0 * std::sin(2.0 * std::numbers::pi * x / 24.0)
                  : 128.0 + 30.0 * std::sin(2.0 * std::numbers::pi * x / 50.0);
  });
  const DisparityResult result = run(paper_config_with_scan(), left, right);
  EXPECT_LT(result.confidence, 0.3f) << "reported " << result.disparity_px;
}

TEST(DisparityScan, ACheckerboardSmallerThanTheWidestWindowIsFoundByItsOutline) {
  // A checkerboard square 96 px wide with 20-px cells over a textured background: the scan's
  // window (36 px) and the next (68 px) lie inside the board and score every 20 px of disparity
  // alike; the widest (132 px) sees the board's outline, which matches at its disparity only.
  // On the scan without wider windows this was found at confidence < 0.1 (never trusted).
  const testing::Texture background(11);
  for (const double object_d : {73.5, -41.0, 128.25}) {
    const auto [left, right] = layered_pair(object_d, 6.0, 48, [&](double x, int y, int l) {
      if (l == 0) return background(x, y);
      const int parity = (static_cast<int>(std::floor(x / 10.0)) + y / 10) % 2;
      return parity != 0 ? 180.0 : 80.0;
    });
    const DisparityResult result = run(paper_config_with_scan(), left, right);
    ASSERT_TRUE(result.valid) << object_d;
    EXPECT_NEAR(result.disparity_px, object_d, 1.0) << object_d;
    EXPECT_GT(result.confidence, 0.3f) << object_d;
  }
}

TEST(DisparityScan, AFinePeriodicTextureIsMatchedWhereItsOutlineIsNot) {
  // A small near ball: each eye sees its own occluding contour, so its outline and its shading
  // (a dome of brightness, fixed to the outline here) are not at the surface's disparity (a
  // 3-cm ball 0.7 m away has them 5 px apart, a nearer one more). Here a 49-px object's outline
  // and shading are at texture_d + 7 px; its texture is a checker of 4-px cells at the middle,
  // widening away from it (as a ball's foreshortening makes its periods differ), too fine for the
  // scan's 4-px blocks, which see the shading and outline. The finer levels refined the scan's
  // estimate within 4 px, where the alias one period from the truth lies, and reported it at level
  // 0 (here 7 px off at 61 and 101; in the simulator the eyes verged 0.5 deg off a checkered ball).
  const testing::Texture background(21);
  const auto shading = [](double x, int y) {
    const double r = std::hypot(x - kWidth / 2, y - kHeight / 2) / 24.0;
    return 70.0 * std::cos(0.5 * std::numbers::pi * std::min(r, 1.0));
  };
  const auto checker = [](double x, int y) {
    const double u = (x - kWidth / 2) / 24.0;
    const int i = static_cast<int>(std::floor(6.0 * (u + 0.3 * u * u * u)));
    const int j = static_cast<int>(std::floor(y / 4.0));
    return (i + j) % 2 != 0 ? 30.0 : -30.0;
  };
  for (const double texture_d : {20.0, -40.0, 61.0, 101.0, -77.0, 150.0}) {
    const double outline_d = texture_d + 7.0;
    const double background_d = texture_d - 30.0;
    hal::Image left(kWidth, kHeight, hal::PixelFormat::kGrey8);
    hal::Image right(kWidth, kHeight, hal::PixelFormat::kGrey8);
    const auto inside = [](double x, int y) {
      return std::abs(x - kWidth / 2) <= 24.0 && std::abs(y - kHeight / 2) <= 24;
    };
    const auto grey = [](double v) {
      return static_cast<std::uint8_t>(std::clamp(std::lround(v), 0L, 255L));
    };
    for (int y = 0; y < kHeight; ++y) {
      for (int x = 0; x < kWidth; ++x) {
        left.row(y)[x] =
            grey(inside(x, y) ? 90.0 + shading(x, y) + checker(x, y) : background(x, y));
        right.row(y)[x] = grey(inside(x + outline_d, y)
                                   ? 90.0 + shading(x + outline_d, y) + checker(x + texture_d, y)
                                   : background(x + background_d, y));
      }
    }
    const DisparityResult result = run(paper_config_with_scan(), left, right);
    ASSERT_TRUE(result.valid) << texture_d;
    EXPECT_EQ(result.level, 0) << texture_d;
    EXPECT_NEAR(result.disparity_px, texture_d, 1.0)
        << texture_d << " (outline at " << outline_d << ")";
  }
}

TEST(DisparityScan, HorizontalStripesAreMatchedByTheObjectsOutlineNotByNoise) {
  // Horizontal stripes on the object and on the background (at another disparity): inside the
  // object no window varies along x (the aperture problem), so the fovea's levels must not move
  // the estimate (they did, by up to 8 px, at high confidence); the object's vertical edges,
  // seen by a wider window, give its disparity.
  for (const double object_d : {50.0, -17.5, 6.0}) {
    const auto [left, right] = layered_pair(object_d, 20.0, 26, [](double, int y, int l) {
      return l == 1 ? 110.0 + 40.0 * std::sin(2.0 * std::numbers::pi * y / 9.0)
                    : 150.0 + 50.0 * std::sin(2.0 * std::numbers::pi * y / 14.0);
    });
    const DisparityResult result = run(paper_config_with_scan(), left, right);
    ASSERT_TRUE(result.valid) << object_d;
    EXPECT_NEAR(result.disparity_px, object_d, 1.5) << object_d;
    EXPECT_TRUE(result.per_level[0].aperture) << object_d;
    EXPECT_TRUE(result.per_level[1].aperture) << object_d;
    EXPECT_FALSE(result.per_level[0].valid || result.per_level[1].valid) << object_d;
  }
}

TEST(DisparityScan, StripesAlmostAlongXWithVerticalDisparityAreNeverConfidentlyWrong) {
  // A face 104 px wide with stripes tilted 0.3 deg from horizontal, and the right eye's rows one
  // pixel lower (vertical disparity, as for a target below the eyes and off to the side). Inside
  // the face neighbouring shifts score within 0.001 of each other: the scan's own window (36 px)
  // and the next (68 px) see a plateau whose top the tilt and the face's border set, not the
  // depth. They decided it, 20-25 px off at confidence 0.44-0.48, before the scan asked for a
  // localized peak. A wider window may find the face's vertical edges; whatever the scan
  // reports, a disparity off the truth must not be trusted.
  const double slope = std::tan(0.3 * std::numbers::pi / 180.0);
  const testing::Texture background(12);
  for (const double object_d : {37.0, -64.0, 112.5}) {
    const auto [left, right] = layered_pair(
        object_d, 8.0, 52,
        [&](double x, int y, int l) {
          return l == 1 ? 128.0 + 60.0 * std::sin(2.0 * std::numbers::pi * (y + slope * x) / 10.0)
                        : background(x, y);
        },
        1);
    const DisparityResult result = run(paper_config_with_scan(), left, right);
    EXPECT_TRUE(!result.valid || std::abs(result.disparity_px - object_d) <= 2.0 ||
                result.confidence < 0.3f)
        << object_d << ": " << result.disparity_px << " at " << result.confidence;
  }
}

TEST(DisparityScan, AFlatProfileIsNeverDecisive) {
  // Stripes over the whole view with no outline anywhere: every shift scores alike, a plateau
  // with no peak. A plateau has no second local maximum either; that must not make its first
  // shift (the range's end) a decisive match at the fovea's window.
  const auto [left, right] = layered_pair(40.0, 40.0, 100, [](double, int y, int) {
    return 128.0 + 50.0 * std::sin(2.0 * std::numbers::pi * y / 11.0);
  });
  const DisparityResult result = run(paper_config_with_scan(), left, right);
  EXPECT_EQ(result.scan_window_tier, DisparityScan::kWindowTiers - 1)
      << result.disparity_px << " at " << result.confidence;
  EXPECT_EQ(result.candidates, 0) << result.disparity_px << " at " << result.confidence;
  EXPECT_TRUE(!result.valid || result.confidence < 0.3f)
      << result.disparity_px << " at " << result.confidence;
}

TEST(DisparityScan, AnUntexturedObjectGivesNoConfidentMatch) {
  const testing::Texture background(9);
  const auto [left, right] = layered_pair(
      100.0, 10.0, 100, [&](double x, int y, int l) { return l == 1 ? 140.0 : background(x, y); });
  const DisparityResult result = run(paper_config_with_scan(), left, right);
  EXPECT_TRUE(!result.valid || result.confidence < 0.3f)
      << result.disparity_px << " at " << result.confidence;
}

TEST(DisparityScan, TheSsmWithTheScanDoesNotAllocateAfterConfigure) {
  const testing::Texture texture(3);
  const hal::Image left = testing::render(texture, kWidth, kHeight);
  const hal::Image right = testing::render(texture, kWidth, kHeight, 150.0, 0.0);
  SensoryServo servo(paper_config_with_scan(), kWidth, kHeight);
  SsmFrame frame = servo.make_frame();
  FeatureRequest request;
  const PixelPoint centre{kWidth / 2, kHeight / 2};
  ASSERT_EQ(servo.process(left, right, centre, centre, request, frame), hal::Status::kOk);
  const std::uint64_t before = runtime::thread_allocation_count();
  for (int k = 0; k < 5; ++k) {
    ASSERT_EQ(servo.process(left, right, centre, centre, request, frame), hal::Status::kOk);
  }
  EXPECT_EQ(runtime::thread_allocation_count() - before, 0u);
  EXPECT_NEAR(frame.summary.disparity.disparity_px, 150.0, 0.5);
}

TEST(DisparityScan, IsOffWithoutARangeAndPicksTheLevelWhoseWindowSpansTheFovea) {
  SsmConfig config = paper_config_with_scan();
  const OperatorBank bank(config.operators, 16, 16);
  const DisparityScan scan(config.disparity, config.operators, bank, config.retina, kWidth,
                           kHeight);
  EXPECT_TRUE(scan.enabled());
  EXPECT_EQ(scan.level(), 2) << "9 samples of 4 px: the first window of at least 32 px";
  config.disparity.scan_range_px = 0.0;
  EXPECT_FALSE(
      DisparityScan(config.disparity, config.operators, bank, config.retina, kWidth, kHeight)
          .enabled());
}

}  // namespace
}  // namespace cambio::perception
