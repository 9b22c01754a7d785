// The zero-disparity filter on drawn stereo pairs whose geometry is known: an object at zero
// disparity in front of a backdrop seen 7 px apart by the two eyes.
#include "cambio/perception/fixated_region.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>

namespace cambio::perception {
namespace {

constexpr int kWidth = 640;
constexpr int kHeight = 480;
constexpr PixelPoint kFixation{320, 240};
constexpr int kBackdropDisparityPx = 7;

/// A rectangle centred `centre_x`, `centre_y` px from the fixation, `width` x `height` px.
struct Rectangle {
  double centre_x, centre_y, width, height;
  bool contains(int x, int y) const {
    return std::abs(x - kFixation.x - centre_x) < 0.5 * width &&
           std::abs(y - kFixation.y - centre_y) < 0.5 * height;
  }
};

/// Grey noise, uncorrelated from one px to the next (a backdrop of fine dots): at another
/// disparity no cell of it looks the same.
std::uint8_t noise(int x, int y, std::uint32_t seed) {
  std::uint32_t h = static_cast<std::uint32_t>(x) * 73856093u ^
                    static_cast<std::uint32_t>(y) * 19349663u ^ seed * 83492791u;
  h ^= h >> 13;
  h *= 0x5bd1e995u;
  h ^= h >> 15;
  return static_cast<std::uint8_t>(40 + h % 176);
}

/// One eye's image: the backdrop shifted by `backdrop_dx` px, and the object shifted by
/// `object_dx`: horizontal stripes (the texture no horizontal shift can be read from), or noise.
hal::Image eye(const Rectangle& object, int backdrop_dx, int object_dx, bool stripes = true) {
  hal::Image image(kWidth, kHeight, hal::PixelFormat::kGrey8);
  for (int y = 0; y < kHeight; ++y) {
    for (int x = 0; x < kWidth; ++x) {
      if (!object.contains(x + object_dx, y)) {
        image.row(y)[x] = noise(x + backdrop_dx, y, 1);
      } else if (stripes) {
        image.row(y)[x] = static_cast<std::uint8_t>(std::lround(128.0 + 70.0 * std::cos(0.35 * y)));
      } else {
        image.row(y)[x] = noise(x + object_dx, y, 2);
      }
    }
  }
  return image;
}

TEST(FixatedRegion, IsTheObjectAtZeroDisparityAndStopsAtItsOutline) {
  const Rectangle object{30.0, -10.0, 96.0, 64.0};
  const hal::Image left = eye(object, 0, 0);
  const hal::Image right = eye(object, kBackdropDisparityPx, 0);
  ZeroDisparityFilter filter{FixatedRegionConfig{}};
  FixatedRegion region;
  filter.find(left, kFixation, right, kFixation, region);
  ASSERT_TRUE(region.valid);
  EXPECT_FALSE(region.clipped);
  // Only cells wholly on the object match (an outline cell sees the backdrop in one eye): the
  // region's centre is the object's to half a cell, its box the object's to one cell.
  EXPECT_NEAR(region.centroid_x_px, object.centre_x, 4.0);
  EXPECT_NEAR(region.centroid_y_px, object.centre_y, 4.0);
  EXPECT_NEAR(region.left_px, object.centre_x - 0.5 * object.width, 8.0);
  EXPECT_NEAR(region.right_px, object.centre_x + 0.5 * object.width, 8.0);
  EXPECT_NEAR(region.top_px, object.centre_y - 0.5 * object.height, 8.0);
  EXPECT_NEAR(region.bottom_px, object.centre_y + 0.5 * object.height, 8.0);
  // (96 / 8 - 1) x (64 / 8 - 1) interior cells at least, and not much of the backdrop.
  EXPECT_GE(region.cells, 11 * 7);
  EXPECT_LE(region.cells, 13 * 9);
  // The outline stops it: outside the object no cell joins.
  for (int row = 0; row < filter.cells_per_side(); ++row) {
    for (int column = 0; column < filter.cells_per_side(); ++column) {
      const double x = (column + 0.5) * 8 - 128;
      const double y = (row + 0.5) * 8 - 128;
      if (std::abs(x - object.centre_x) > 0.5 * object.width + 8.0 ||
          std::abs(y - object.centre_y) > 0.5 * object.height + 8.0) {
        EXPECT_FALSE(filter.in_region(column, row)) << column << ", " << row;
      }
    }
  }
}

TEST(FixatedRegion, ThereIsNoneWhenNothingAtTheFixationIsAtZeroDisparity) {
  // A textured object as far as the backdrop: both 7 px apart, nothing the eyes are verged on.
  // (Horizontal stripes would match at every shift: the filter cannot tell their depth either.)
  const Rectangle object{0.0, 0.0, 96.0, 64.0};
  const hal::Image left = eye(object, 0, 0, false);
  const hal::Image right = eye(object, kBackdropDisparityPx, kBackdropDisparityPx, false);
  ZeroDisparityFilter filter{FixatedRegionConfig{}};
  FixatedRegion region;
  filter.find(left, kFixation, right, kFixation, region);
  EXPECT_FALSE(region.valid);
}

TEST(FixatedRegion, FollowsEachEyesFixationAndMarksARegionCutByTheWindow) {
  // The right eye fixates 5 px further right: the same object, drawn there, is still at zero
  // disparity relative to the fixations.
  ZeroDisparityFilter filter{FixatedRegionConfig{}};
  FixatedRegion region;
  const Rectangle object{-20.0, 12.0, 96.0, 64.0};
  filter.find(eye(object, 0, 0), kFixation, eye(object, kBackdropDisparityPx - 5, -5),
              {kFixation.x + 5, kFixation.y}, region);
  ASSERT_TRUE(region.valid);
  EXPECT_FALSE(region.clipped);
  EXPECT_NEAR(region.centroid_x_px, object.centre_x, 4.0);
  EXPECT_NEAR(region.centroid_y_px, object.centre_y, 4.0);
  // An object wider than the 256-px window is cut by it.
  const Rectangle wide{0.0, 0.0, 400.0, 64.0};
  filter.find(eye(wide, 0, 0), kFixation, eye(wide, kBackdropDisparityPx, 0), kFixation, region);
  EXPECT_TRUE(region.valid);
  EXPECT_TRUE(region.clipped);
}

}  // namespace
}  // namespace cambio::perception
