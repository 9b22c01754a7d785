// PNG pixels through libpng (png_errors.hpp: how its errors come back).
#include <png.h>

#include <bit>
#include <csetjmp>
#include <cstring>
#include <string>

#include "decoded_pixels.hpp"
#include "png_errors.hpp"

namespace cambio::app {

namespace {

struct PngReadState {
  std::span<const std::uint8_t> bytes;
  std::size_t offset = 0;
};

void read_from_bytes(png_structp png, png_bytep out, png_size_t length) {
  auto* state = static_cast<PngReadState*>(png_get_io_ptr(png));
  if (length > state->bytes.size() - state->offset) png_error(png, "the file ends inside a chunk");
  std::memcpy(out, state->bytes.data() + state->offset, length);
  state->offset += length;
}

struct PngReader {
  png_structp png = nullptr;
  png_infop info = nullptr;
  PngReader() = default;
  PngReader(const PngReader&) = delete;
  PngReader& operator=(const PngReader&) = delete;
  ~PngReader() { png_destroy_read_struct(&png, info != nullptr ? &info : nullptr, nullptr); }
};

struct PngShape {
  int width_px = 0;
  int height_px = 0;
  int channels = 0;
  int bit_depth = 0;
};

// Reads the whole image into `raw` (8 or 16-bit samples, 16-bit in host order); false when
// libpng reports an error (its message in the error pointer's PngErrorText).
bool read_png(PngReader& reader, PngReadState& state, PngShape& shape,
              std::vector<std::uint8_t>& raw, std::vector<png_bytep>& rows) {
  if (setjmp(png_jmpbuf(reader.png)) != 0) return false;
  png_set_read_fn(reader.png, &state, &read_from_bytes);
  png_set_user_limits(reader.png, kMaxImageSidePx, kMaxImageSidePx);
  png_read_info(reader.png, reader.info);
  const int colour_type = png_get_color_type(reader.png, reader.info);
  const int bit_depth = png_get_bit_depth(reader.png, reader.info);
  if (colour_type == PNG_COLOR_TYPE_PALETTE) png_set_palette_to_rgb(reader.png);
  if (colour_type == PNG_COLOR_TYPE_GRAY && bit_depth < 8) {
    png_set_expand_gray_1_2_4_to_8(reader.png);
  }
  // Expanding a palette or low-depth grey turns a tRNS chunk into alpha: dropped like alpha.
  if ((colour_type & PNG_COLOR_MASK_ALPHA) != 0 ||
      png_get_valid(reader.png, reader.info, PNG_INFO_tRNS) != 0) {
    png_set_strip_alpha(reader.png);
  }
  if (bit_depth == 16 && std::endian::native == std::endian::little) png_set_swap(reader.png);
  png_set_interlace_handling(reader.png);
  png_read_update_info(reader.png, reader.info);
  shape.width_px = static_cast<int>(png_get_image_width(reader.png, reader.info));
  shape.height_px = static_cast<int>(png_get_image_height(reader.png, reader.info));
  shape.channels = png_get_channels(reader.png, reader.info);
  shape.bit_depth = png_get_bit_depth(reader.png, reader.info);
  if ((shape.channels != 1 && shape.channels != 3) ||
      (shape.bit_depth != 8 && shape.bit_depth != 16) ||
      static_cast<std::int64_t>(shape.width_px) * shape.height_px > kMaxImagePixels) {
    png_error(reader.png, "an unexpected sample layout after expansion");
  }
  const std::size_t stride = png_get_rowbytes(reader.png, reader.info);
  raw.resize(stride * static_cast<std::size_t>(shape.height_px));
  rows.resize(static_cast<std::size_t>(shape.height_px));
  for (std::size_t y = 0; y < rows.size(); ++y) rows[y] = raw.data() + y * stride;
  png_read_image(reader.png, rows.data());
  png_read_end(reader.png, nullptr);
  return true;
}

}  // namespace

DecodedPixels decode_png_pixels(std::span<const std::uint8_t> bytes) {
  PngReadState state{bytes};
  PngErrorText error;
  PngReader reader;
  reader.png =
      png_create_read_struct(PNG_LIBPNG_VER_STRING, &error, &keep_png_error, &ignore_png_warning);
  if (reader.png != nullptr) reader.info = png_create_info_struct(reader.png);
  if (reader.info == nullptr) throw std::bad_alloc();
  PngShape shape;
  std::vector<std::uint8_t> raw;
  std::vector<png_bytep> rows;
  if (!read_png(reader, state, shape, raw, rows)) throw DamagedPixels(error.text);
  DecodedPixels pixels{shape.width_px, shape.height_px, shape.channels, {}};
  if (shape.bit_depth == 8) {
    pixels.samples = std::move(raw);
    return pixels;
  }
  pixels.samples.resize(raw.size() / 2);
  for (std::size_t i = 0; i < pixels.samples.size(); ++i) {
    std::uint16_t value = 0;
    std::memcpy(&value, raw.data() + 2 * i, sizeof value);
    pixels.samples[i] = scaled_to_8_bits(value);
  }
  return pixels;
}

}  // namespace cambio::app
