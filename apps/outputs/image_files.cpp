#include "image_files.hpp"

#include <algorithm>
#include <cerrno>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <memory>
#include <vector>

#include "decoded_pixels.hpp"

namespace cambio::app {

namespace {

const char* container_name(ImageContainer container) {
  switch (container) {
    case ImageContainer::kPng:
      return "PNG";
    case ImageContainer::kJpeg:
      return "JPEG";
    case ImageContainer::kPnm:
      return "PGM/PPM";
  }
  return "image";
}

void check_size(const std::string& name, const char* what, std::int64_t width,
                std::int64_t height) {
  const std::string size = std::to_string(width) + "x" + std::to_string(height) + " px";
  if (width < 1 || height < 1) throw ImageFileError(name + ": " + what + " an empty image");
  if (width > kMaxImageSidePx || height > kMaxImageSidePx || width * height > kMaxImagePixels) {
    throw ImageFileError(name + ": " + what + " a " + size + " image; images are read up to " +
                         std::to_string(kMaxImageSidePx) + " px a side and " +
                         std::to_string(kMaxImagePixels >> 20) + " Mpx");
  }
}

DecodedPixels decode_pixels(std::span<const std::uint8_t> bytes, const ImageHeader& header) {
  switch (header.container) {
    case ImageContainer::kPng:
      return decode_png_pixels(bytes);
    case ImageContainer::kJpeg:
      return decode_jpeg_pixels(bytes);
    case ImageContainer::kPnm:
      break;
  }
  return decode_pnm_pixels(bytes, header);
}

// Grey from RGB with ITU-R BT.601 luma weights (0.299, 0.587, 0.114) in 15-bit fixed point,
// rounded: OpenCV 4.6's COLOR_RGB2GRAY to the last bit (the same on a million random colours),
// so a colour file reads as it did when OpenCV decoded it.
std::uint8_t luma(const std::uint8_t* rgb) {
  return static_cast<std::uint8_t>((rgb[0] * 9798 + rgb[1] * 19235 + rgb[2] * 3735 + 16384) >> 15);
}

hal::Image converted_to(const DecodedPixels& pixels, hal::PixelFormat format) {
  hal::Image image(pixels.width_px, pixels.height_px, format);
  const std::size_t count =
      static_cast<std::size_t>(pixels.width_px) * static_cast<std::size_t>(pixels.height_px);
  const std::uint8_t* from = pixels.samples.data();
  std::uint8_t* to = image.pixels.data();
  if (pixels.channels == image.channels()) {
    std::copy(from, from + count * static_cast<std::size_t>(pixels.channels), to);
  } else if (format == hal::PixelFormat::kGrey8) {
    for (std::size_t p = 0; p < count; ++p) to[p] = luma(from + 3 * p);
  } else {
    for (std::size_t p = 0; p < count; ++p) to[3 * p] = to[3 * p + 1] = to[3 * p + 2] = from[p];
  }
  return image;
}

}  // namespace

hal::Image decode_image(std::span<const std::uint8_t> bytes, const std::string& name,
                        hal::PixelFormat format) {
  if (bytes.empty()) throw ImageFileError(name + ": empty file");
  const std::optional<ImageHeader> header = read_image_header(bytes);
  if (!header) {
    throw ImageFileError(name +
                         ": not an image this program reads (a PNG, JPEG, PGM or PPM file with a "
                         "complete and valid header)");
  }
  check_size(name, "declares", header->width_px, header->height_px);
  DecodedPixels pixels;
  try {
    pixels = decode_pixels(bytes, *header);
  } catch (const DamagedPixels& damage) {
    throw ImageFileError(name + ": a damaged " + container_name(header->container) +
                         " file (its pixels cannot be decoded: " + damage.what() + ")");
  }
  // EXIF orientation may have turned the image; the decoder may disagree with the header.
  check_size(name, "decodes to", pixels.width_px, pixels.height_px);
  return converted_to(pixels, format);
}

hal::Image read_image_file(const std::string& path, hal::PixelFormat format) {
  std::error_code error;
  const auto status = std::filesystem::status(path, error);
  if (!std::filesystem::exists(status)) throw ImageFileError(path + ": no such file");
  if (std::filesystem::is_directory(status)) {
    throw ImageFileError(path + ": a directory, not an image file");
  }
  const std::unique_ptr<std::FILE, int (*)(std::FILE*)> file(std::fopen(path.c_str(), "rb"),
                                                             &std::fclose);
  if (!file) throw ImageFileError(path + ": cannot open: " + std::strerror(errno));
  // Read in pieces up to the bound: the size of a pipe or device is known only at its end.
  std::vector<std::uint8_t> bytes;
  std::vector<std::uint8_t> piece(std::size_t{1} << 20);
  for (;;) {
    const std::size_t got = std::fread(piece.data(), 1, piece.size(), file.get());
    bytes.insert(bytes.end(), piece.begin(), piece.begin() + static_cast<std::ptrdiff_t>(got));
    if (static_cast<std::int64_t>(bytes.size()) > kMaxImageFileBytes) {
      throw ImageFileError(path + ": larger than " + std::to_string(kMaxImageFileBytes >> 20) +
                           " MB, more than any image this program reads needs");
    }
    if (got < piece.size()) break;
  }
  if (std::ferror(file.get()) != 0) {
    throw ImageFileError(path + ": cannot read: " + std::strerror(errno));
  }
  return decode_image(bytes, path, format);
}

}  // namespace cambio::app
