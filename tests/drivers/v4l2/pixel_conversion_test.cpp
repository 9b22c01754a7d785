// YUYV and GREY frames into the HAL's grey8 and rgb8 images, against BT.601's real-valued
// matrix (ITU-R BT.601-7, limited range: Y' in [16, 235], Cb and Cr in [16, 240]).

#include "cambio/v4l2/pixel_conversion.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>
#include <vector>

#include "cambio/v4l2/device_modes.hpp"

namespace cambio::v4l2 {
namespace {

// The closed form: R'G'B' = 255/219 (Y'-16) + M (Cb-128, Cr-128) with Kr = 0.299, Kb = 0.114.
std::array<double, 3> bt601_rgb(int y, int cb, int cr) {
  const double luma = 255.0 / 219.0 * (y - 16);
  const double b_diff = 255.0 / 224.0 * (cb - 128);
  const double r_diff = 255.0 / 224.0 * (cr - 128);
  const double r = luma + 2.0 * (1.0 - 0.299) * r_diff;
  const double b = luma + 2.0 * (1.0 - 0.114) * b_diff;
  const double g = (luma - 0.299 * r - 0.114 * b) / 0.587;
  const auto clamp = [](double v) { return std::clamp(v, 0.0, 255.0); };
  return {clamp(r), clamp(g), clamp(b)};
}

std::vector<std::uint8_t> random_yuyv(int width, int height, std::size_t stride, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_int_distribution<int> byte(0, 255);
  std::vector<std::uint8_t> frame(stride * static_cast<std::size_t>(height));
  for (auto& b : frame) b = static_cast<std::uint8_t>(byte(rng));
  (void)width;
  return frame;
}

TEST(V4l2PixelConversion, YuyvToRgbIsBt601WithinOneLevel) {
  const int width = 64;
  const int height = 9;
  const std::size_t stride = 2 * width + 12;  // Padded rows, as drivers align them.
  const auto frame = random_yuyv(width, height, stride, 7);
  hal::Image out(width, height, hal::PixelFormat::kRgb8);
  ASSERT_EQ(convert_frame(kFourccYuyv, frame, stride, out), hal::Status::kOk);
  for (int y = 0; y < height; ++y) {
    for (int x = 0; x < width; ++x) {
      const std::uint8_t* in = frame.data() + static_cast<std::size_t>(y) * stride;
      const auto truth = bt601_rgb(in[2 * x], in[4 * (x / 2) + 1], in[4 * (x / 2) + 3]);
      for (int c = 0; c < 3; ++c) {
        ASSERT_LE(std::abs(out.row(y)[3 * x + c] - truth[static_cast<std::size_t>(c)]), 1.0)
            << "pixel (" << x << ", " << y << ") channel " << c;
      }
    }
  }
}

TEST(V4l2PixelConversion, YuyvLimitedRangeEndsAreBlackAndWhite) {
  // Y' 16 with neutral chroma is black, Y' 235 white; nothing beyond clips the other way.
  const std::vector<std::uint8_t> frame = {16, 128, 235, 128, 0, 128, 255, 128};
  hal::Image rgb(4, 1, hal::PixelFormat::kRgb8);
  ASSERT_EQ(convert_frame(kFourccYuyv, frame, 8, rgb), hal::Status::kOk);
  EXPECT_EQ(rgb.pixels,
            (std::vector<std::uint8_t>{0, 0, 0, 255, 255, 255, 0, 0, 0, 255, 255, 255}));
  hal::Image grey(4, 1, hal::PixelFormat::kGrey8);
  ASSERT_EQ(convert_frame(kFourccYuyv, frame, 8, grey), hal::Status::kOk);
  EXPECT_EQ(grey.pixels, (std::vector<std::uint8_t>{0, 255, 0, 255}));
}

TEST(V4l2PixelConversion, YuyvToGreyIsTheExpandedLuma) {
  const int width = 32;
  const auto frame = random_yuyv(width, 4, 2 * width, 11);
  hal::Image out(width, 4, hal::PixelFormat::kGrey8);
  ASSERT_EQ(convert_frame(kFourccYuyv, frame, 2 * width, out), hal::Status::kOk);
  for (std::size_t i = 0; i < out.pixels.size(); ++i) {
    const double truth = std::clamp(255.0 / 219.0 * (frame[2 * i] - 16), 0.0, 255.0);
    ASSERT_LE(std::abs(out.pixels[i] - truth), 0.5 + 1e-9) << "pixel " << i;
  }
}

TEST(V4l2PixelConversion, GreyIsCopiedOrReplicatedWithoutTheRowPadding) {
  const std::vector<std::uint8_t> frame = {1, 2, 3, 99, 4, 5, 6, 99};  // 3x2, stride 4
  hal::Image grey(3, 2, hal::PixelFormat::kGrey8);
  ASSERT_EQ(convert_frame(kFourccGrey, frame, 4, grey), hal::Status::kOk);
  EXPECT_EQ(grey.pixels, (std::vector<std::uint8_t>{1, 2, 3, 4, 5, 6}));
  hal::Image rgb(3, 2, hal::PixelFormat::kRgb8);
  ASSERT_EQ(convert_frame(kFourccGrey, frame, 4, rgb), hal::Status::kOk);
  EXPECT_EQ(rgb.pixels,
            (std::vector<std::uint8_t>{1, 1, 1, 2, 2, 2, 3, 3, 3, 4, 4, 4, 5, 5, 5, 6, 6, 6}));
}

TEST(V4l2PixelConversion, AShortFrameOrUnknownFormatIsRejected) {
  hal::Image out(4, 2, hal::PixelFormat::kGrey8);
  const std::vector<std::uint8_t> short_frame(15);
  EXPECT_EQ(convert_frame(kFourccYuyv, short_frame, 8, out), hal::Status::kRejected);
  EXPECT_EQ(convert_frame(kFourccGrey, short_frame, 3, out), hal::Status::kRejected);
  EXPECT_EQ(convert_frame(fourcc('M', 'J', 'P', 'G'), std::vector<std::uint8_t>(64), 8, out),
            hal::Status::kRejected);
  EXPECT_FALSE(can_convert(fourcc('M', 'J', 'P', 'G'), hal::PixelFormat::kRgb8));
}

}  // namespace
}  // namespace cambio::v4l2
