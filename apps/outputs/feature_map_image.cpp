#include "feature_map_image.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>

#include <opencv2/imgproc.hpp>

namespace cambio::app {

bool is_signed_map(const perception::MapSpec& spec) {
  switch (spec.kind) {
    case perception::MapKind::kGaussian:
      return spec.order > 0;
    case perception::MapKind::kLaplacian:
    case perception::MapKind::kSobelX:
    case perception::MapKind::kSobelY:
      return true;
    case perception::MapKind::kIntensity:
    case perception::MapKind::kAverage:
    case perception::MapKind::kUserMask:
      break;
  }
  return false;
}

cv::Mat feature_map_tile(const float* map, int width, int height, bool signed_map, int tile_w,
                         int tile_h) {
  cv::Mat tile(height, width, CV_8U);
  float peak = 0.0f;
  float low = map[0];
  float high = map[0];
  for (int i = 0; i < width * height; ++i) {
    peak = std::max(peak, std::abs(map[i]));
    low = std::min(low, map[i]);
    high = std::max(high, map[i]);
  }
  for (int y = 0; y < height; ++y) {
    for (int x = 0; x < width; ++x) {
      const float v = map[y * width + x];
      float g = 128.0f;
      if (signed_map && peak > 0.0f) g = 128.0f + 127.0f * v / peak;
      if (!signed_map && high > low) g = 255.0f * (v - low) / (high - low);
      tile.at<std::uint8_t>(y, x) = static_cast<std::uint8_t>(std::clamp(std::lround(g), 0L, 255L));
    }
  }
  cv::Mat scaled;
  cv::resize(tile, scaled, cv::Size(tile_w, tile_h), 0, 0,
             tile_w >= width ? cv::INTER_NEAREST : cv::INTER_AREA);
  return scaled;
}

}  // namespace cambio::app
