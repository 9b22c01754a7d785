#pragma once

#include <cstddef>
#include <cstdint>
#include <span>

#include "cambio/hal/image.hpp"
#include "cambio/hal/status.hpp"

namespace cambio::v4l2 {

/// Whether a device's `fourcc` (GREY, YUYV) can be converted into `format`.
bool can_convert(std::uint32_t fourcc, hal::PixelFormat format);

/// Converts one captured frame into `out`, whose size and format were set at configure.
/// GREY is full-range luma: copied (grey8) or replicated (rgb8). YUYV is ITU-R BT.601
/// limited-range Y'CbCr 4:2:2 (Y' in [16, 235]), expanded to full-range R'G'B' with the integer
/// form of BT.601's matrix (the one Microsoft's YUV documentation gives, 8-bit weights):
///   C = Y' - 16, D = Cb - 128, E = Cr - 128
///   R = (298 C + 409 E + 128) >> 8,  G = (298 C - 100 D - 208 E + 128) >> 8,
///   B = (298 C + 516 D + 128) >> 8,  each clamped to [0, 255];
/// grey8 takes the luma alone, round(255 C / 219) clamped, so grey and the colour path's luma
/// agree. `bytes_per_line` is the device's row stride. Returns kRejected when `frame` is shorter
/// than the image needs or the pair cannot be converted. Real-time safe: no allocation.
hal::Status convert_frame(std::uint32_t fourcc, std::span<const std::uint8_t> frame,
                          std::size_t bytes_per_line, hal::Image& out) noexcept;

}  // namespace cambio::v4l2
