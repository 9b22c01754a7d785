#pragma once

#include <cstdint>
#include <span>
#include <vector>

#include "cambio/hal/image.hpp"
#include "cambio/perception/perception_config.hpp"
#include "cambio/perception/retina.hpp"

namespace cambio::perception {

/// The image region of the fixated object, found by a zero-disparity filter: the connected cells
/// around the fixation where the two eyes see the same thing (within `max_disparity_px`), as
/// verged eyes do on the surface they fixate and on nothing nearer or farther. Positions are
/// image px from each eye's fixation point, x right and y down, the same in both eyes (a cell at
/// zero disparity sits at the same offset in both).
struct FixatedRegion {
  bool valid = false;  ///< Enough matching cells around the fixation.
  /// The region reached the searched window's edge: its centre is biased, and its cells and
  /// bounds are those found before (the search stops there).
  bool clipped = false;
  int cells = 0;
  float centroid_x_px = 0.0f;  ///< Mean offset of the region's cells from the fixation point.
  float centroid_y_px = 0.0f;
  float left_px = 0.0f;  ///< Bounding box of the region's cells, from the fixation point.
  float right_px = 0.0f;
  float top_px = 0.0f;
  float bottom_px = 0.0f;
};

/// Finds FixatedRegion. Cells of `cell_px` square on a `cells` x `cells` grid centred on the
/// fixation; each cell's grey level is compared between the eyes by zero-mean normalised
/// correlation over shifts of up to +-max_disparity_px (a fixated surface that is slanted or
/// curved is not at exactly zero disparity everywhere). A cell matches when both eyes' cells have
/// texture and the best correlation reaches `min_correlation`. The region grows from the matching
/// cell nearest the fixation (within `seed_radius_cells`) through its 8-neighbours: the cells on
/// the object's outline see the object in one eye and what lies behind in the other, and do not
/// match, so the region stops there. This is the zero-disparity filter of active stereo heads
/// (the iCub's), used to segment the fixated object from its surround without a model of it.
/// Cells are compared only as the region reaches them (the seed's rings, then the region and its
/// border), so the cost follows the object's size, not the window's.
/// Everything is allocated by the constructor; find() is real-time safe. Not thread-safe.
class ZeroDisparityFilter {
 public:
  /// kUnread: the last find() did not need to compare it.
  enum class Cell : std::uint8_t { kUnread, kOutside, kFlat, kMismatch, kMatch };

  explicit ZeroDisparityFilter(const FixatedRegionConfig& config);

  void find(const hal::Image& left, PixelPoint left_fixation, const hal::Image& right,
            PixelPoint right_fixation, FixatedRegion& out) noexcept;

  /// The last find()'s classification, row-major, cells x cells.
  std::span<const Cell> cell_classes() const { return classes_; }
  /// Whether the cell at (column, row) joined the last region.
  bool in_region(int column, int row) const {
    return region_[static_cast<std::size_t>(row * cells_ + column)] != 0;
  }
  int cells_per_side() const { return cells_; }

 private:
  /// Grey levels of `image` (channel mean) over `width` x `height` px whose top-left corner is
  /// `x0`, `y0`, into `out`; px outside the image are NaN.
  static void read_grey(const hal::Image& image, int x0, int y0, int width, int height,
                        std::vector<float>& out) noexcept;
  /// The cell's class, compared on first use.
  Cell cell(int column, int row) noexcept;
  Cell classify(int column, int row) noexcept;

  FixatedRegionConfig config_;
  int cells_ = 0;
  int cell_px_ = 0;
  int shift_px_ = 0;
  int span_px_ = 0;  ///< cells * cell_px.
  const hal::Image* left_ = nullptr;
  const hal::Image* right_ = nullptr;
  PixelPoint left_fixation_;
  PixelPoint right_fixation_;
  std::vector<float> left_grey_;   ///< One cell: cell x cell.
  std::vector<float> right_grey_;  ///< One cell and the shifts: (cell + 2 shift) x cell.
  std::vector<Cell> classes_;
  std::vector<std::uint8_t> region_;
  std::vector<int> stack_;
};

}  // namespace cambio::perception
