#pragma once

#include <cstdint>
#include <optional>
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

/// The images `read_image_file` accepts. A side of 16384 px is twice the largest camera the sim
/// renders; 64 Mpx (a 16-bit colour decode of 384 MB) keeps a decompression bomb, a few hundred
/// kilobytes of PNG that declare gigapixels, from taking the machine's memory. The file size
/// bound is that of the largest accepted image stored uncompressed, with room for metadata.
inline constexpr int kMaxImageSidePx = 16384;
inline constexpr std::int64_t kMaxImagePixels = std::int64_t{64} << 20;
inline constexpr std::int64_t kMaxImageFileBytes = std::int64_t{512} << 20;

enum class ImageContainer : std::uint8_t { kPng, kJpeg, kPnm };

/// What an image file's header declares, read without decoding any pixel.
struct ImageHeader {
  ImageContainer container = ImageContainer::kPng;
  std::int64_t width_px = 0;
  std::int64_t height_px = 0;
  // PGM/PPM only: the largest sample value the header declares, and where the samples begin
  // (after the one whitespace character that ends the header).
  int pnm_max_value = 0;
  std::size_t pnm_samples_at = 0;
};

/// Reads the container and size from the first bytes of a PNG (IHDR), a JPEG (the first SOFn
/// segment) or a binary or text PGM/PPM (P2, P3, P5, P6); nullopt for anything else or a header
/// cut short. Never reads past `bytes`. Thread-safe; allocates nothing.
std::optional<ImageHeader> read_image_header(std::span<const std::uint8_t> bytes);

/// Decodes the bytes of an image file named `name` (the name is only for messages) and converts
/// it to `format`; 16-bit samples are scaled to 8 bit (value / 257). The container must be one
/// read_image_header knows and the size it declares, like the decoded one, within
/// kMaxImageSidePx and kMaxImagePixels, so no decoder allocates for a size that is refused.
/// Colour is turned grey with OpenCV's weights and rounding (BT.601 luma, 15-bit fixed point).
/// Throws ImageFileError naming `name` and what is wrong. Thread-safe; prints nothing.
hal::Image decode_image(std::span<const std::uint8_t> bytes, const std::string& name,
                        hal::PixelFormat format);

/// Reads a PNG, JPEG or PGM/PPM file (grey or colour, 8 or 16 bit) with decode_image; refuses a
/// missing, unreadable, empty or larger than kMaxImageFileBytes file. Throws ImageFileError
/// naming `path`.
hal::Image read_image_file(const std::string& path, hal::PixelFormat format);

/// An 8-bit grey or RGB image as PNG file bytes (to stage in an OutputDirectory). Throws
/// ImageFileError.
std::vector<std::uint8_t> encode_png(const hal::Image& image);

/// A 16-bit single-channel image (e.g. depth in millimetres, rows packed) as PNG file bytes.
std::vector<std::uint8_t> encode_png16(std::span<const std::uint16_t> samples, int width_px,
                                       int height_px);

}  // namespace cambio::app
