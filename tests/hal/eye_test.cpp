#include "cambio/hal/eye.hpp"

#include <gtest/gtest.h>

namespace cambio::hal {
namespace {

static_assert(static_cast<int>(Eye::kLeft) == 0 && static_cast<int>(Eye::kRight) == 1,
              "per-eye arrays are indexed by Eye, left first");
static_assert(other(Eye::kLeft) == Eye::kRight && other(Eye::kRight) == Eye::kLeft);

TEST(Eye, SpelledAsInConfigFiles) {
  EXPECT_EQ(to_string(Eye::kLeft), "left");
  EXPECT_EQ(to_string(Eye::kRight), "right");
}

}  // namespace
}  // namespace cambio::hal
