#pragma once

#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

namespace cambio::hal {

enum class PixelFormat : std::uint8_t { kGrey8, kRgb8 };

constexpr int channels_of(PixelFormat format) {
  return format == PixelFormat::kRgb8 ? 3 : 1;
}

/// A pinhole camera model in pixels. Principal point measured from the top-left pixel's centre
/// being (0, 0); x to the right, y down.
struct CameraIntrinsics {
  int width_px = 0;
  int height_px = 0;
  double focal_x_px = 0.0;
  double focal_y_px = 0.0;
  double principal_x_px = 0.0;
  double principal_y_px = 0.0;
};

/// An 8-bit image, rows packed without padding (stride = width * channels). The pixel buffer is
/// sized once by `resize()` (at configure time); copying an image into one of the same size
/// reuses its buffer, so a loop that copies frames does not allocate.
struct Image {
  int width_px = 0;
  int height_px = 0;
  PixelFormat format = PixelFormat::kGrey8;
  /// When the frame was exposed, on the clock of the loop that grabbed it (ns).
  std::int64_t stamp_ns = 0;
  /// Increments with every new frame from the same camera; 0 means "never filled".
  std::uint64_t sequence = 0;
  std::vector<std::uint8_t> pixels;

  Image() = default;
  Image(int width, int height, PixelFormat pixel_format) { resize(width, height, pixel_format); }

  /// Allocates. Not real-time safe unless the size is unchanged.
  void resize(int width, int height, PixelFormat pixel_format) {
    width_px = width;
    height_px = height;
    format = pixel_format;
    pixels.resize(static_cast<std::size_t>(width) * static_cast<std::size_t>(height) *
                  static_cast<std::size_t>(channels_of(pixel_format)));
  }
  int channels() const { return channels_of(format); }
  std::size_t stride_bytes() const {
    return static_cast<std::size_t>(width_px) * static_cast<std::size_t>(channels());
  }
  bool empty() const { return pixels.empty(); }
  std::uint8_t* row(int y) { return pixels.data() + static_cast<std::size_t>(y) * stride_bytes(); }
  const std::uint8_t* row(int y) const {
    return pixels.data() + static_cast<std::size_t>(y) * stride_bytes();
  }
  std::span<const std::uint8_t> bytes() const { return pixels; }
};

}  // namespace cambio::hal
