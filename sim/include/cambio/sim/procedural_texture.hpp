#pragma once

#include <array>
#include <cstdint>
#include <span>

#include "cambio/config/scene_config.hpp"

namespace cambio::sim {

/// Fills an RGB8 texture (rows packed, `width_px` x `height_px`) with a procedural pattern that
/// repeats seamlessly every `period_px` texels in both directions (so it can tile a floor).
/// `feature_px` is the size of one feature (checker square, stripe, noise blob, dot) in texels.
/// Colours are the object's rgb and the texture's second_rgb (0..1). Deterministic for the
/// texture's pattern_seed. Not real-time safe (called while building the world).
void fill_procedural_texture(const config::TextureConfig& texture, std::array<double, 3> rgb,
                             double feature_px, int width_px, int height_px,
                             std::span<std::uint8_t> rgb_out);

}  // namespace cambio::sim
