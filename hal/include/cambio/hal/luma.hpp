#pragma once

#include <cstdint>

namespace cambio::hal {

/// The grey level of an sRGB pixel: ITU-R BT.601 luma (0.299 R + 0.587 G + 0.114 B) in 8.8 fixed
/// point, rounded. The weights 77 + 150 + 29 sum to 256, so white stays 255. Every conversion of
/// an rgb8 image to grey8 (sim cameras, the retina) goes through this one, so a grey camera and
/// the retina's colour path see the same levels. Real-time safe.
constexpr std::uint8_t luma_bt601(std::uint8_t r, std::uint8_t g, std::uint8_t b) {
  return static_cast<std::uint8_t>((77u * r + 150u * g + 29u * b + 128u) >> 8);
}

}  // namespace cambio::hal
