#pragma once

#include <cstdint>
#include <span>
#include <stdexcept>
#include <vector>

#include "image_files.hpp"

namespace cambio::app {

/// An image file's pixels as its decoder delivers them, before conversion to a hal::PixelFormat:
/// 8-bit samples (16-bit ones already scaled), grey (1 channel) or RGB (3), rows packed.
struct DecodedPixels {
  int width_px = 0;
  int height_px = 0;
  int channels = 1;
  std::vector<std::uint8_t> samples;
};

/// Pixels that cannot be decoded; the message says why, without the file's name (decode_image
/// adds it).
class DamagedPixels : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

/// A 16-bit sample scaled to 8 bits, rounded to nearest: round(value / 257).
constexpr std::uint8_t scaled_to_8_bits(std::uint16_t value) {
  return static_cast<std::uint8_t>((static_cast<unsigned>(value) + 128U) / 257U);
}

/// Each decoder takes the bytes of a whole file whose header read_image_header read (and whose
/// declared size is within the bounds) and throws DamagedPixels when its pixels cannot be
/// decoded. Palette PNGs are expanded to RGB; alpha and transparency are dropped.
DecodedPixels decode_png_pixels(std::span<const std::uint8_t> bytes);
/// Baseline and progressive JPEG, grey, YCbCr or (Adobe) CMYK, turned as its EXIF orientation
/// says. A file that ends before its last scan is damaged, not filled with grey.
DecodedPixels decode_jpeg_pixels(std::span<const std::uint8_t> bytes);
/// Binary or text PGM/PPM; samples are scaled from the file's largest value to 255.
DecodedPixels decode_pnm_pixels(std::span<const std::uint8_t> bytes, const ImageHeader& header);

}  // namespace cambio::app
