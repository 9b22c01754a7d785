#pragma once

#include <vector>

#include "cambio/perception/lens_distortion.hpp"

namespace cambio::perception {

/// Where every pixel corner of a camera's ideal (pinhole) image lies in the image its lens makes,
/// evaluated once at configure time: a retina reading through the lens looks up its blocks'
/// corners (they are pixel corners, as its origins and block sizes are whole pixels) instead of
/// evaluating the model for every window it builds. Corners beyond the table (a field-covering
/// level's apron, far outside the image) are evaluated on demand.
///
/// Coordinates are pixel-edge ones: corner (x, y) is the top-left corner of pixel (x, y), so the
/// image spans corners [0, width] x [0, height].
class LensCornerMap {
 public:
  /// The identity (no lens).
  LensCornerMap() = default;
  /// Tabulates the corners of a width x height image and a margin of `margin_px` around it
  /// (allocates (width + 1 + 2 margin) x (height + 1 + 2 margin) pairs of floats).
  LensCornerMap(const LensDistortion& lens, int width_px, int height_px, int margin_px = 32);

  bool is_identity() const { return lens_.is_identity(); }
  const LensDistortion& lens() const { return lens_; }

  /// The distorted pixel-edge position of ideal corner (x, y). Real-time safe.
  void corner_px(int x, int y, double& u, double& v) const noexcept {
    const int column = x + margin_px_;
    const int row = y + margin_px_;
    if (column >= 0 && column < columns_ && row >= 0 && row < rows_) {
      const float* at = table_.data() + 2 * (static_cast<std::ptrdiff_t>(row) * columns_ + column);
      u = at[0];
      v = at[1];
      return;
    }
    evaluate(x, y, u, v);
  }

 private:
  void evaluate(int x, int y, double& u, double& v) const noexcept {
    // The model takes pixel centres: corner (x, y) is centre coordinate (x - 0.5, y - 0.5).
    lens_.distort_px(x - 0.5, y - 0.5, u, v);
    u += 0.5;
    v += 0.5;
  }

  LensDistortion lens_;
  int margin_px_ = 0;
  int columns_ = 0;
  int rows_ = 0;
  std::vector<float> table_;  ///< (u, v) per corner, rows_ x columns_.
};

}  // namespace cambio::perception
