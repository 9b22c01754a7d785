#include "foveated_frame.hpp"

#include <cstring>

#include "cambio/hal/luma.hpp"

namespace cambio::sim {

namespace {

// Writes `count` rgb pixels of `source` into `target` in out's format, each repeated `repeat`
// times.
void write_pixels(const std::uint8_t* source, int count, int repeat, bool grey,
                  std::uint8_t* target) noexcept {
  if (grey) {
    for (int x = 0; x < count; ++x, source += 3) {
      const std::uint8_t value = hal::luma_bt601(source[0], source[1], source[2]);
      for (int k = 0; k < repeat; ++k) *target++ = value;
    }
  } else if (repeat == 1) {
    std::memcpy(target, source, static_cast<std::size_t>(count) * 3);
  } else {
    for (int x = 0; x < count; ++x, source += 3) {
      for (int k = 0; k < repeat; ++k, target += 3) {
        target[0] = source[0];
        target[1] = source[1];
        target[2] = source[2];
      }
    }
  }
}

}  // namespace

void compose_foveated(const std::uint8_t* periphery_rgb_bottom_up, int downscale,
                      const std::uint8_t* fovea_rgb_bottom_up, int fovea_px,
                      hal::Image& out) noexcept {
  const int width = out.width_px;
  const int height = out.height_px;
  const int periphery_width = width / downscale;
  const int periphery_height = height / downscale;
  const bool grey = out.format == hal::PixelFormat::kGrey8;
  const std::size_t channels = grey ? 1 : 3;
  const std::size_t out_row_bytes = static_cast<std::size_t>(width) * channels;
  const std::size_t periphery_row_bytes = static_cast<std::size_t>(periphery_width) * 3;
  const std::size_t fovea_row_bytes = static_cast<std::size_t>(fovea_px) * 3;
  const int fovea_x0 = (width - fovea_px) / 2;
  const int fovea_y0 = (height - fovea_px) / 2;
  for (int py = 0; py < periphery_height; ++py) {
    const std::uint8_t* source =
        periphery_rgb_bottom_up +
        static_cast<std::size_t>(periphery_height - 1 - py) * periphery_row_bytes;
    const int y_first = py * downscale;
    write_pixels(source, periphery_width, downscale, grey, out.row(y_first));
    for (int y = y_first + 1; y < y_first + downscale; ++y) {
      std::memcpy(out.row(y), out.row(y_first), out_row_bytes);
    }
  }
  for (int fy = 0; fy < fovea_px; ++fy) {
    const std::uint8_t* source =
        fovea_rgb_bottom_up + static_cast<std::size_t>(fovea_px - 1 - fy) * fovea_row_bytes;
    write_pixels(source, fovea_px, 1, grey,
                 out.row(fovea_y0 + fy) + static_cast<std::size_t>(fovea_x0) * channels);
  }
}

}  // namespace cambio::sim
