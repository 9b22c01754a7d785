#include "cambio/hal/luma.hpp"

#include <gtest/gtest.h>

#include <cmath>

namespace cambio::hal {
namespace {

static_assert(luma_bt601(0, 0, 0) == 0);
static_assert(luma_bt601(255, 255, 255) == 255);

TEST(Luma, GreysKeepTheirLevel) {
  // The weights sum to 256, so r = g = b = v gives v exactly.
  for (int v = 0; v < 256; ++v) {
    const auto level = static_cast<std::uint8_t>(v);
    EXPECT_EQ(luma_bt601(level, level, level), level);
  }
}

TEST(Luma, WithinOneLevelOfTheBt601Formula) {
  for (int r = 0; r < 256; r += 15) {
    for (int g = 0; g < 256; g += 15) {
      for (int b = 0; b < 256; b += 15) {
        const double exact = 0.299 * r + 0.587 * g + 0.114 * b;
        const int luma = luma_bt601(static_cast<std::uint8_t>(r), static_cast<std::uint8_t>(g),
                                    static_cast<std::uint8_t>(b));
        EXPECT_LE(std::abs(luma - exact), 1.0) << r << "," << g << "," << b;
      }
    }
  }
}

}  // namespace
}  // namespace cambio::hal
