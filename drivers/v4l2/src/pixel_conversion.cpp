#include "cambio/v4l2/pixel_conversion.hpp"

#include <algorithm>
#include <array>
#include <cstring>

#include "cambio/v4l2/device_modes.hpp"

namespace cambio::v4l2 {

namespace {

std::uint8_t clamp_byte(int value) {
  return static_cast<std::uint8_t>(std::clamp(value, 0, 255));
}

// Limited-range luma expanded to full range, exactly rounded: round(255 (Y' - 16) / 219).
constexpr std::array<std::uint8_t, 256> kExpandedLuma = [] {
  std::array<std::uint8_t, 256> table{};
  for (int y = 0; y < 256; ++y) {
    const int c = std::clamp(y - 16, 0, 219);
    table[static_cast<std::size_t>(y)] = static_cast<std::uint8_t>((2 * 255 * c + 219) / (2 * 219));
  }
  return table;
}();

int source_bytes_per_pixel(std::uint32_t fourcc) {
  return fourcc == kFourccYuyv ? 2 : 1;
}

void grey_row(const std::uint8_t* in, int width, hal::PixelFormat format, std::uint8_t* out) {
  if (format == hal::PixelFormat::kGrey8) {
    std::memcpy(out, in, static_cast<std::size_t>(width));
    return;
  }
  for (int x = 0; x < width; ++x) out[3 * x] = out[3 * x + 1] = out[3 * x + 2] = in[x];
}

// One YUYV macropixel (Y0 Cb Y1 Cr) covers two pixels that share Cb and Cr.
void yuyv_row(const std::uint8_t* in, int width, hal::PixelFormat format, std::uint8_t* out) {
  if (format == hal::PixelFormat::kGrey8) {
    for (int x = 0; x < width; ++x) out[x] = kExpandedLuma[in[2 * x]];
    return;
  }
  for (int x = 0; x < width; ++x) {
    const std::uint8_t* pair = in + 4 * (x / 2);
    const int c = in[2 * x] - 16;
    const int d = pair[1] - 128;
    const int e = pair[3] - 128;
    std::uint8_t* rgb = out + 3 * x;
    rgb[0] = clamp_byte((298 * c + 409 * e + 128) >> 8);
    rgb[1] = clamp_byte((298 * c - 100 * d - 208 * e + 128) >> 8);
    rgb[2] = clamp_byte((298 * c + 516 * d + 128) >> 8);
  }
}

}  // namespace

bool can_convert(std::uint32_t fourcc, hal::PixelFormat format) {
  return (fourcc == kFourccGrey || fourcc == kFourccYuyv) &&
         (format == hal::PixelFormat::kGrey8 || format == hal::PixelFormat::kRgb8);
}

hal::Status convert_frame(std::uint32_t fourcc, std::span<const std::uint8_t> frame,
                          std::size_t bytes_per_line, hal::Image& out) noexcept {
  if (!can_convert(fourcc, out.format) || out.width_px <= 0 || out.height_px <= 0) {
    return hal::Status::kRejected;
  }
  // A YUYV row holds whole macropixels: an odd width still ends on a full Y0 Cb Y1 Cr.
  const std::size_t row_bytes = fourcc == kFourccYuyv
                                    ? 4 * ((static_cast<std::size_t>(out.width_px) + 1) / 2)
                                    : static_cast<std::size_t>(out.width_px) *
                                          static_cast<std::size_t>(source_bytes_per_pixel(fourcc));
  if (bytes_per_line < row_bytes ||
      frame.size() < bytes_per_line * static_cast<std::size_t>(out.height_px - 1) + row_bytes ||
      out.pixels.size() != out.stride_bytes() * static_cast<std::size_t>(out.height_px)) {
    return hal::Status::kRejected;
  }
  for (int y = 0; y < out.height_px; ++y) {
    const std::uint8_t* in = frame.data() + static_cast<std::size_t>(y) * bytes_per_line;
    if (fourcc == kFourccYuyv) {
      yuyv_row(in, out.width_px, out.format, out.row(y));
    } else {
      grey_row(in, out.width_px, out.format, out.row(y));
    }
  }
  return hal::Status::kOk;
}

}  // namespace cambio::v4l2
