// The synthetic images' renderer against the texture's closed form, pixel by pixel: the shifted
// renders every disparity and motion test measures against must be the texture they claim.
#include "synthetic_images.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <utility>

namespace cambio::perception {
namespace {

TEST(SyntheticImages, RenderIsTheTextureRoundedAtEveryPixelAndShift) {
  for (const auto& [dx, dy] : {std::pair{0.0, 0.0}, {2.4, 0.0}, {-41.3, 7.25}}) {
    const testing::Texture texture(7);
    const hal::Image image = testing::render(texture, 97, 61, dx, dy);
    int off_by_rounding = 0;
    for (int y = 0; y < image.height_px; ++y) {
      for (int x = 0; x < image.width_px; ++x) {
        const double truth = std::clamp(texture(x + dx, y + dy), 0.0, 255.0);
        const int rendered = image.row(y)[x];
        // The product form differs from one cosine in the last bits: only a value within that of
        // a rounding boundary may round the other way.
        ASSERT_LE(std::abs(rendered - truth), 0.5 + 1e-9) << x << "," << y << " shift " << dx;
        if (rendered != std::lround(truth)) ++off_by_rounding;
      }
    }
    EXPECT_EQ(off_by_rounding, 0) << "shift " << dx << "," << dy;
  }
}

}  // namespace
}  // namespace cambio::perception
