#pragma once

#include <cstdint>

#include "cambio/hal/image.hpp"

namespace cambio::sim {

/// Composes a foveated eye image (config::SimFoveationConfig) into `out` (top row first, rgb8 or
/// grey8 through hal::luma_bt601): the periphery, rendered at 1 / downscale of out's size,
/// upsampled by repeating each pixel over a downscale x downscale square, and the centred
/// fovea_px x fovea_px full-resolution window over it. Both inputs are rgb, bottom row first, as
/// OpenGL reads them back. Real-time safe; one pass over the output.
void compose_foveated(const std::uint8_t* periphery_rgb_bottom_up, int downscale,
                      const std::uint8_t* fovea_rgb_bottom_up, int fovea_px,
                      hal::Image& out) noexcept;

}  // namespace cambio::sim
