#pragma once

#include <cstdint>
#include <span>
#include <stdexcept>
#include <string>
#include <vector>

#include "cambio/hal/image.hpp"

namespace cambio::app {

/// An image file that cannot be read or written; the message names the file and why.
class ImageFileError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

/// Reads a PNG or JPEG (grey or colour, 8 or 16 bit) and converts it to `format`. 16-bit
/// samples are scaled to 8 bit (value / 257). Throws ImageFileError.
hal::Image read_image_file(const std::string& path, hal::PixelFormat format);

/// An 8-bit grey or RGB image as PNG file bytes (to stage in an OutputDirectory). Throws
/// ImageFileError.
std::vector<std::uint8_t> encode_png(const hal::Image& image);

/// A 16-bit single-channel image (e.g. depth in millimetres, rows packed) as PNG file bytes.
std::vector<std::uint8_t> encode_png16(std::span<const std::uint16_t> samples, int width_px,
                                       int height_px);

/// Writes an 8-bit grey or RGB image as PNG. Throws ImageFileError.
void write_png(const std::string& path, const hal::Image& image);

/// Writes a 16-bit single-channel PNG (e.g. depth in millimetres), rows packed.
void write_png16(const std::string& path, std::span<const std::uint16_t> samples, int width_px,
                 int height_px);

}  // namespace cambio::app
