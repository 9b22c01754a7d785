#pragma once

#include <array>
#include <cstdint>
#include <memory>
#include <vector>

#include "cambio/hal/image.hpp"
#include "cambio/hal/status.hpp"
#include "cambio/perception/lens_corner_map.hpp"
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

/// Through a lens, a block whose footprint fits 8 x 8 pixels of a grey image (levels of 1 to 4 px
/// blocks): its sample is a weighted sum of rows of 8 bytes from `offset`, the first and last
/// row and column weighted by the share of them the footprint covers, read for many blocks at
/// once. Internal to Retina.
struct LensWindow {
  static constexpr int kSize = 8;
  std::int32_t sample = 0;   ///< Index into the level's samples.
  std::int32_t offset = 0;   ///< Byte offset of the window's top-left pixel.
  std::int16_t columns = 0;  ///< 2 to kSize: columns beyond weigh 0.
  std::int16_t rows = 0;     ///< 2 to kSize.
  float x_before = 0.0f;     ///< The first column's share; the last column's is x_after.
  float x_after = 0.0f;
  float y_before = 0.0f;  ///< The first row's share; the last row's is y_after.
  float y_after = 0.0f;
  float inverse_area = 0.0f;
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

  /// Reads the camera's lens from now on (configure time: tabulates the lens's pixel corners for
  /// the image size given to the constructor): every sample is then the mean of the *ideal*
  /// (pinhole) image over its block, read from the distorted image over the block's footprint
  /// there, so the levels, and all that is computed from them, see the undistorted geometry. An
  /// identity lens reads pixels as they are. Through a lens, build() takes images of the
  /// constructor's size only (kRejected otherwise).
  void set_lens(const LensDistortion& lens);
  /// The same with a table shared with the eye's other retinas (null: no lens). A retina whose
  /// window moves between a few places every frame (a disparity search's shifted window) keeps
  /// `plans_per_level` plans of each level, so that it plans a place once, not every frame.
  void set_lens(std::shared_ptr<const LensCornerMap> lens, int plans_per_level = 1);

  /// Builds all levels from a grey8 or rgb8 image. An rgb8 pixel is converted with
  /// hal::luma_bt601 where a level reads it, so the levels equal those of the image converted to
  /// grey8 first, without converting whole rows.
  /// Real-time safe: no allocation. kRejected for an empty image (or, through a lens, one of
  /// another size than the constructor's).
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
  /// Through a lens, how one block is read: its footprint in the distorted image, planned once
  /// per scale and origin (plan_level_through_lens) so that a build only sums pixels.
  struct LensBlockPlan {
    enum class Kind : std::uint8_t {
      kWindow,  ///< Small, inside a grey image: one of the level's LensWindows.
      kInside,  ///< Whole pixels [x_lo, x_hi) x [y_lo, y_hi) and the shares of those around.
      kAtEdge,  ///< Reaching past an edge: the rectangle [x_before, x_after) x [y_before, y_after).
      kBeyondEdge,  ///< Wholly beyond edge x_lo (left, right, top, bottom): [x_before, x_after)
                    ///< along it.
      kNearest,     ///< Off a corner, or folded over by the model: pixel (x_lo, y_lo).
    };
    Kind kind = Kind::kNearest;
    std::int16_t x_lo = 0;
    std::int16_t x_hi = 0;
    std::int16_t y_lo = 0;
    std::int16_t y_hi = 0;
    float x_before = 0.0f;
    float x_after = 0.0f;
    float y_before = 0.0f;
    float y_after = 0.0f;
    float inverse_area = 0.0f;
    /// kInside: > 0 at the first block of a run sharing one pass down columns [run_first_px,
    /// run_end_px), -1 for the run's other blocks, 0 outside runs.
    std::int16_t run_first_px = 0;
    std::int16_t run_end_px = 0;
  };
  /// Through a lens, a level planned for one scale, origin and image size.
  struct LensPlan {
    std::vector<LensBlockPlan> blocks;
    std::vector<LensWindow> windows;  ///< Capacity for every block, reserved by set_lens().
    std::array<int, 6> key{};         ///< Scale, origin x and y, image width, height, format.
    float fraction_inside = 1.0f;
    std::uint64_t last_used = 0;
  };

  struct Level {
    std::vector<float> samples;  ///< (width + 2 apron) x (height + 2 apron).
    int scale_px = 1;
    int origin_x_px = 0;
    int origin_y_px = 0;
    float fraction_inside = 1.0f;
    /// Through a lens: what each block reads (LensBlockPlan), for the scale, origin and image
    /// size they were planned for.
    std::vector<LensPlan> lens_plans;  ///< Through a lens: set_lens()'s count of them.
  };
  bool can_read(const hal::Image& image) const noexcept;
  void build_level(const hal::Image& image, Level& level) noexcept;
  void build_level_through_lens(const hal::Image& image, Level& level) noexcept;
  void plan_level_through_lens(const hal::Image& image, const Level& level,
                               LensPlan& plan) noexcept;
  void mark_column_runs(LensPlan& level_plan, int blocks_per_row) const noexcept;
  void integrate_image_edges(const hal::Image& image) noexcept;
  template <int kChannels>
  double footprint_sum(const hal::Image& image, const LensBlockPlan& plan) noexcept;

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
  int image_width_px_ = 0;
  int image_height_px_ = 0;
  std::shared_ptr<const LensCornerMap> lens_;  ///< Null unless set_lens() gave a lens.
  /// Through a lens: two rows of block corners (x, y pairs), the block row's top and bottom.
  std::vector<double> corner_rows_;
  /// Through a lens: prefix sums along the image's four edge rows and columns (left, right, top,
  /// bottom), for blocks beyond the edges; computed once per build, when a level needs them.
  std::array<std::vector<std::uint32_t>, 4> edge_sums_;
  bool edge_sums_ready_ = false;
  std::uint64_t lens_builds_ = 0;  ///< Orders the plans' last use.
};

}  // namespace cambio::perception
