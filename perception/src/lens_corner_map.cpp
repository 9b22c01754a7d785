#include "cambio/perception/lens_corner_map.hpp"

#include <stdexcept>

namespace cambio::perception {

LensCornerMap::LensCornerMap(const LensDistortion& lens, int width_px, int height_px, int margin_px)
    : lens_(lens), margin_px_(margin_px) {
  if (width_px <= 0 || height_px <= 0 || margin_px < 0) {
    throw std::invalid_argument("a lens corner map needs a positive image size");
  }
  if (lens_.is_identity()) return;
  columns_ = width_px + 1 + 2 * margin_px;
  rows_ = height_px + 1 + 2 * margin_px;
  table_.resize(2 * static_cast<std::size_t>(columns_) * static_cast<std::size_t>(rows_));
  float* at = table_.data();
  for (int row = 0; row < rows_; ++row) {
    for (int column = 0; column < columns_; ++column, at += 2) {
      double u = 0.0;
      double v = 0.0;
      evaluate(column - margin_px_, row - margin_px_, u, v);
      at[0] = static_cast<float>(u);
      at[1] = static_cast<float>(v);
    }
  }
}

}  // namespace cambio::perception
