#pragma once

#include <cstdint>
#include <string>
#include <vector>

namespace cambio::v4l2 {

/// A V4L2 pixel format code (v4l2_fourcc), e.g. 'YUYV'.
constexpr std::uint32_t fourcc(char a, char b, char c, char d) {
  return static_cast<std::uint32_t>(static_cast<unsigned char>(a)) |
         (static_cast<std::uint32_t>(static_cast<unsigned char>(b)) << 8) |
         (static_cast<std::uint32_t>(static_cast<unsigned char>(c)) << 16) |
         (static_cast<std::uint32_t>(static_cast<unsigned char>(d)) << 24);
}
inline constexpr std::uint32_t kFourccGrey = fourcc('G', 'R', 'E', 'Y');
inline constexpr std::uint32_t kFourccYuyv = fourcc('Y', 'U', 'Y', 'V');
inline constexpr std::uint32_t kFourccMjpeg = fourcc('M', 'J', 'P', 'G');

/// "YUYV" from the code, as v4l2-ctl prints it.
std::string fourcc_text(std::uint32_t code);

/// Seconds per frame as V4L2 gives it (v4l2_fract): numerator / denominator.
struct FrameInterval {
  std::uint32_t numerator = 0;
  std::uint32_t denominator = 0;
  /// Frames per second; 0 for an unset interval.
  double rate_hz() const {
    return numerator == 0 ? 0.0 : static_cast<double>(denominator) / numerator;
  }
};

/// One frame size a format offers: discrete (min == max, step 0) or a stepwise range. The rates
/// it offers at that size; empty when the driver does not enumerate them (any rate is asked for
/// and the driver's answer read back).
struct FrameSizeOffer {
  int min_width_px = 0;
  int max_width_px = 0;
  int step_width_px = 0;
  int min_height_px = 0;
  int max_height_px = 0;
  int step_height_px = 0;
  std::vector<FrameInterval> intervals;

  static FrameSizeOffer discrete(int width_px, int height_px,
                                 std::vector<FrameInterval> intervals = {}) {
    return {width_px, width_px, 0, height_px, height_px, 0, std::move(intervals)};
  }
  bool is_discrete() const {
    return min_width_px == max_width_px && min_height_px == max_height_px;
  }
  bool contains(int width_px, int height_px) const;
};

/// A pixel format the device offers (VIDIOC_ENUM_FMT) with its sizes (VIDIOC_ENUM_FRAMESIZES)
/// and each size's rates (VIDIOC_ENUM_FRAMEINTERVALS).
struct FormatOffer {
  std::uint32_t fourcc = 0;
  std::vector<FrameSizeOffer> sizes;
};

using DeviceModes = std::vector<FormatOffer>;

}  // namespace cambio::v4l2
