#pragma once

#include <opencv2/core.hpp>

#include "cambio/perception/operator_bank.hpp"

namespace cambio::app {

/// A feature map as an 8-bit grey picture for people. Derivative-like (signed) maps: grey with
/// 128 at zero and +-127 at the map's largest magnitude; smoothing-like maps (intensity,
/// averages, g0) stretched from their minimum to maximum. Scaled to tile_w x tile_h: enlarged
/// by whole pixels, reduced by area averaging.
/// Derivatives (Gaussian orders 1 and 2, the Laplacian, Sobel) are signed: zero is mid-grey.
/// Intensity, g0, averages and user masks are stretched.
bool is_signed_map(const perception::MapSpec& spec);

cv::Mat feature_map_tile(const float* map, int width, int height, bool signed_map, int tile_w,
                         int tile_h);

}  // namespace cambio::app
