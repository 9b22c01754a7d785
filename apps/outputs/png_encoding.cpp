// PNG files through libpng, tuned for speed as OpenCV's encoder is by default (SUB filter,
// zlib level 1, run-length strategy): results are written as a run ends, often many at once.
// png_errors.hpp says how libpng's errors come back.
#include <png.h>
#include <zlib.h>

#include <algorithm>
#include <bit>
#include <csetjmp>
#include <string>

#include "image_files.hpp"
#include "png_errors.hpp"

namespace cambio::app {

namespace {

struct PngWriteState {
  std::vector<std::uint8_t>* out = nullptr;
};

void append_to_bytes(png_structp png, png_bytep data, png_size_t length) {
  auto* state = static_cast<PngWriteState*>(png_get_io_ptr(png));
  bool appended = true;
  try {
    state->out->insert(state->out->end(), data, data + length);
  } catch (const std::bad_alloc&) {
    appended = false;
  }
  if (!appended) png_error(png, "out of memory");
}

struct PngWriter {
  png_structp png = nullptr;
  png_infop info = nullptr;
  PngWriter() = default;
  PngWriter(const PngWriter&) = delete;
  PngWriter& operator=(const PngWriter&) = delete;
  ~PngWriter() { png_destroy_write_struct(&png, info != nullptr ? &info : nullptr); }
};

struct PngPicture {
  const std::uint8_t* samples = nullptr;  // rows packed, 16-bit samples in host order
  int width_px = 0;
  int height_px = 0;
  int channels = 1;  // grey or RGB
  int bit_depth = 8;
};

bool write_png(PngWriter& writer, PngWriteState& state, const PngPicture& picture) {
  if (setjmp(png_jmpbuf(writer.png)) != 0) return false;
  png_set_write_fn(writer.png, &state, &append_to_bytes, nullptr);
  png_set_IHDR(writer.png, writer.info, static_cast<png_uint_32>(picture.width_px),
               static_cast<png_uint_32>(picture.height_px), picture.bit_depth,
               picture.channels == 3 ? PNG_COLOR_TYPE_RGB : PNG_COLOR_TYPE_GRAY, PNG_INTERLACE_NONE,
               PNG_COMPRESSION_TYPE_DEFAULT, PNG_FILTER_TYPE_DEFAULT);
  png_set_filter(writer.png, PNG_FILTER_TYPE_BASE, PNG_FILTER_SUB);
  png_set_compression_level(writer.png, Z_BEST_SPEED);
  png_set_compression_strategy(writer.png, Z_RLE);
  png_write_info(writer.png, writer.info);
  if (picture.bit_depth == 16 && std::endian::native == std::endian::little) {
    png_set_swap(writer.png);
  }
  const std::size_t stride = static_cast<std::size_t>(picture.width_px) *
                             static_cast<std::size_t>(picture.channels * picture.bit_depth / 8);
  for (int y = 0; y < picture.height_px; ++y) {
    png_write_row(writer.png, picture.samples + static_cast<std::size_t>(y) * stride);
  }
  png_write_end(writer.png, nullptr);
  return true;
}

std::vector<std::uint8_t> encode(const PngPicture& picture, const std::string& what) {
  if (picture.width_px < 1 || picture.height_px < 1) {
    throw ImageFileError(what + ": could not encode as PNG: an empty image");
  }
  std::vector<std::uint8_t> bytes;
  PngWriteState state{&bytes};
  PngErrorText error;
  PngWriter writer;
  writer.png =
      png_create_write_struct(PNG_LIBPNG_VER_STRING, &error, &keep_png_error, &ignore_png_warning);
  if (writer.png != nullptr) writer.info = png_create_info_struct(writer.png);
  if (writer.info == nullptr) throw std::bad_alloc();
  if (!write_png(writer, state, picture)) {
    throw ImageFileError(what + ": could not encode as PNG: " + error.text);
  }
  return bytes;
}

}  // namespace

std::vector<std::uint8_t> encode_png(const hal::Image& image) {
  const std::string what =
      std::to_string(image.width_px) + "x" + std::to_string(image.height_px) + " image";
  if (image.pixels.size() !=
      image.stride_bytes() * static_cast<std::size_t>(std::max(image.height_px, 0))) {
    throw ImageFileError(what + ": could not encode as PNG: its pixels do not fill it");
  }
  return encode({image.pixels.data(), image.width_px, image.height_px, image.channels(), 8}, what);
}

std::vector<std::uint8_t> encode_png16(std::span<const std::uint16_t> samples, int width_px,
                                       int height_px) {
  if (width_px < 0 || height_px < 0 ||
      samples.size() != static_cast<std::size_t>(width_px) * static_cast<std::size_t>(height_px)) {
    throw ImageFileError("16-bit image: sample count does not match " + std::to_string(width_px) +
                         "x" + std::to_string(height_px));
  }
  return encode({reinterpret_cast<const std::uint8_t*>(samples.data()), width_px, height_px, 1, 16},
                "16-bit image");
}

}  // namespace cambio::app
