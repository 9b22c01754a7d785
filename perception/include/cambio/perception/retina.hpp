#pragma once

#include <cstdint>
#include <vector>

#include "cambio/hal/image.hpp"
#include "cambio/hal/status.hpp"
#include "cambio/perception/lens_distortion.hpp"
#include "cambio/perception/perception_config.hpp"

namespace cambio::perception {

/// A pixel of the source image (x right, y down, 0-based).
struct PixelPoint {
  int x = 0;
  int y = 0;
};

/// One level of a retina: width x height samples, each the mean of a scale x scale block of the
/// source image, plus `apron` samples of real data on every side so that kernels up to that
/// half-width see no artificial border. Values are grey levels in [0, 255].
struct RetinaLevelView {
  const float* interior = nullptr;  ///< Sample (0, 0); rows `stride` floats apart.
  int stride = 0;
  int width = 0;
  int height = 0;
  int apron = 0;  ///< interior[-apron * stride - apron] is valid.
  int scale_px = 1;
  /// Source coordinates of the left/top edge of block (0, 0) of the interior.
  int origin_x_px = 0;
  int origin_y_px = 0;
  /// Fraction of the level's source footprint (interior and apron) inside the image; below 1
  /// the border policy (replicate the nearest edge pixel) supplied the rest.
  float fraction_inside = 1.0f;

  float at(int x, int y) const { return interior[y * stride + x]; }
  /// Source pixel-centre coordinate of level coordinate `level_x` (both continuous).
  double to_source_x(double level_x) const {
    return origin_x_px + (level_x + 0.5) * scale_px - 0.5;
  }
  double to_source_y(double level_y) const {
    return origin_y_px + (level_y + 0.5) * scale_px - 0.5;
  }
  double to_level_x(double source_x) const {
    return (source_x - origin_x_px + 0.5) / scale_px - 0.5;
  }
  double to_level_y(double source_y) const {
    return (source_y - origin_y_px + 0.5) / scale_px - 0.5;
  }
};

/// The multi-resolution ("retina") image of paper Section 3 for one eye.
///
/// Level k (block size b = 2^k, or wider for a coarsest level covering the field) spans source
/// columns [fx - (width/2) b, fx + (width - width/2) b) around the fixation pixel (fx, fy), so the
/// sample at (width/2, height/2) of level 0 is the fixation pixel and every level shares that
/// corner point. Border policy: samples whose blocks reach outside the image use the nearest
/// edge pixel (replicate), and each level reports the fraction of real data it holds.
///
/// Levels are built straight from the source (block sums, no full-resolution intermediate), each
/// source pixel a level covers read once: parts of a level beyond the image (its apron, or all
/// around for a field-covering level) reuse the edge rows' and columns' sums instead of reading
/// the edge pixels again, so a field-covering level is one streaming pass over the image.
class Retina {
 public:
  /// Allocates every level. `apron_px` is the largest kernel half-width that will be applied;
  /// the image size bounds the block size of a coarsest level that covers the field.
  /// Throws std::invalid_argument on a non-positive size or more than kMaxLevels levels.
  Retina(const RetinaConfig& config, int apron_px, int image_width_px, int image_height_px);

  static constexpr int kMaxLevels = 8;

  /// Reads the camera's lens from now on (configure time: allocates each level's footprint
  /// table): every sample is then the mean of the *ideal* (pinhole) image over its block, read
  /// from the distorted image over the block's footprint there, so the levels, and all that is
  /// computed from them, see the undistorted geometry. An identity lens reads pixels as they are.
  void set_lens(const LensDistortion& lens);

  /// Builds all levels from a grey8 or rgb8 image. An rgb8 pixel is converted with
  /// hal::luma_bt601 where a level reads it, so the levels equal those of the image converted to
  /// grey8 first, without converting whole rows.
  /// Real-time safe: no allocation. kRejected for an empty image.
  hal::Status build(const hal::Image& image, PixelPoint fixation) noexcept;

  /// Builds level k alone at `fixation`; the other levels and fixation() keep what they held
  /// (a scratch retina whose window follows a disparity estimate). Real-time safe; kRejected
  /// for an empty image or k out of range.
  hal::Status build_one_level(const hal::Image& image, int k, PixelPoint fixation) noexcept;

  int levels() const { return static_cast<int>(levels_.size()); }
  int width() const { return width_; }
  int height() const { return height_; }
  int apron() const { return apron_; }
  PixelPoint fixation() const { return fixation_; }
  RetinaLevelView level(int k) const;

  /// The block size of level k for an image of the given size (depends on the fixation only
  /// when the coarsest level covers the field; capped at what the constructor provisioned).
  int scale_of(int k, int image_width, int image_height, PixelPoint fixation) const;

 private:
  struct Level {
    std::vector<float> samples;  ///< (width + 2 apron) x (height + 2 apron).
    int scale_px = 1;
    int origin_x_px = 0;
    int origin_y_px = 0;
    float fraction_inside = 1.0f;
    /// Through a lens: the distorted position of every block corner, (width + 2 apron + 1) x
    /// (height + 2 apron + 1) pairs (x, y), for the scale and origin it was computed at.
    std::vector<double> corners_px;
    int corners_scale_px = 0;
    int corners_origin_x_px = 0;
    int corners_origin_y_px = 0;
  };
  void build_level(const hal::Image& image, Level& level) noexcept;
  void build_level_through_lens(const hal::Image& image, Level& level) noexcept;

  RetinaConfig config_;
  int width_ = 0;
  int height_ = 0;
  int apron_ = 0;
  int max_scale_ = 1;
  PixelPoint fixation_;
  std::vector<Level> levels_;
  /// Per source column read, summed over a block's rows; 16 bits while 257 x 255 < 2^16
  /// (twice the lanes per vector add), 32 bits only for blocks of more rows.
  std::vector<std::uint16_t> column_sums16_;
  std::vector<std::uint32_t> column_sums_;
  LensDistortion lens_;  ///< Identity unless set_lens() gave one.
};

}  // namespace cambio::perception
