#include "cambio/perception/retina.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <stdexcept>

#include "pixel_sums.hpp"

namespace cambio::perception {

namespace {

int ceil_div(int a, int b) {
  return (a + b - 1) / b;
}

using pixel_sums::add_row;
using pixel_sums::kMaxRows16;
using pixel_sums::reduce_blocks;
using pixel_sums::sum_rows;

// The source positions [start, start + n) clamped to [0, size) (replicate): positions [first,
// end) are read, `before` positions fall before the edge and map onto `first`, `after` fall past
// it and map onto end - 1; the rest are inside, once each. size > 0, n > 0.
struct ClampedSpan {
  int first = 0;
  int end = 0;
  int before = 0;
  int after = 0;
  int inside(int n) const { return n - before - after; }
  bool operator==(const ClampedSpan&) const = default;
};

ClampedSpan clamp_span(int start, int n, int size) {
  ClampedSpan span;
  span.first = std::clamp(start, 0, size - 1);
  span.end = std::clamp(start + n - 1, 0, size - 1) + 1;
  span.before = std::clamp(span.first - start, 0, n);
  span.after = std::clamp(start + n - span.end, 0, n);
  return span;
}

}  // namespace

Retina::Retina(const RetinaConfig& config, int apron_px, int image_width_px, int image_height_px)
    : config_(config),
      width_(config.width_px),
      height_(config.height_px),
      apron_(apron_px),
      image_width_px_(std::max(image_width_px, 1)),
      image_height_px_(std::max(image_height_px, 1)) {
  if (config.levels < 1 || config.levels > kMaxLevels) {
    throw std::invalid_argument("retina levels must be in [1, 8]");
  }
  if (width_ < 2 || height_ < 2 || apron_ < 0) {
    throw std::invalid_argument("retina levels must be at least 2 x 2 with a non-negative apron");
  }
  max_scale_ = 1 << (config.levels - 1);
  if (config.coarsest_covers_field) {
    max_scale_ = std::max({max_scale_, ceil_div(std::max(image_width_px, 1), width_ / 2),
                           ceil_div(std::max(image_height_px, 1), height_ / 2)});
  }
  const std::size_t padded_w = static_cast<std::size_t>(width_ + 2 * apron_);
  const std::size_t padded_h = static_cast<std::size_t>(height_ + 2 * apron_);
  levels_.resize(static_cast<std::size_t>(config.levels));
  for (auto& level : levels_) level.samples.assign(padded_w * padded_h, 0.0f);
  column_sums16_.assign(padded_w * static_cast<std::size_t>(std::min(max_scale_, kMaxRows16)), 0u);
  if (max_scale_ > kMaxRows16) {
    column_sums_.assign(padded_w * static_cast<std::size_t>(max_scale_), 0u);
  }
}

int Retina::scale_of(int k, int image_width, int image_height, PixelPoint fixation) const {
  const int octave = 1 << k;
  if (!config_.coarsest_covers_field || k != levels() - 1) return octave;
  // Smallest block size whose level reaches both image edges from the fixation point.
  const int left = width_ / 2;
  const int right = width_ - left;
  const int top = height_ / 2;
  const int bottom = height_ - top;
  const int needed = std::max({octave, ceil_div(std::max(fixation.x, 0), left),
                               ceil_div(std::max(image_width - fixation.x, 0), right),
                               ceil_div(std::max(fixation.y, 0), top),
                               ceil_div(std::max(image_height - fixation.y, 0), bottom)});
  return std::min(needed, max_scale_);
}

bool Retina::can_read(const hal::Image& image) const noexcept {
  if (image.empty() || image.width_px <= 0 || image.height_px <= 0) return false;
  // A lens model (and its tables) is for one image size.
  return !lens_ || (image.width_px == image_width_px_ && image.height_px == image_height_px_);
}

hal::Status Retina::build(const hal::Image& image, PixelPoint fixation) noexcept {
  if (!can_read(image)) return hal::Status::kRejected;
  fixation_ = fixation;
  edge_sums_ready_ = false;
  for (int k = 0; k < levels(); ++k) {
    Level& level = levels_[static_cast<std::size_t>(k)];
    level.scale_px = scale_of(k, image.width_px, image.height_px, fixation);
    level.origin_x_px = fixation.x - (width_ / 2) * level.scale_px;
    level.origin_y_px = fixation.y - (height_ / 2) * level.scale_px;
    build_level(image, level);
  }
  return hal::Status::kOk;
}

hal::Status Retina::build_one_level(const hal::Image& image, int k, PixelPoint fixation) noexcept {
  if (!can_read(image) || k < 0 || k >= levels()) return hal::Status::kRejected;
  edge_sums_ready_ = false;
  Level& level = levels_[static_cast<std::size_t>(k)];
  level.scale_px = scale_of(k, image.width_px, image.height_px, fixation);
  level.origin_x_px = fixation.x - (width_ / 2) * level.scale_px;
  level.origin_y_px = fixation.y - (height_ / 2) * level.scale_px;
  build_level(image, level);
  return hal::Status::kOk;
}

void Retina::build_level(const hal::Image& image, Level& level) noexcept {
  if (lens_) {
    build_level_through_lens(image, level);
    return;
  }
  const int b = level.scale_px;
  const int padded_w = width_ + 2 * apron_;
  const int padded_h = height_ + 2 * apron_;
  const int span_w = padded_w * b;  // Source columns under the level, apron included.
  const int x0 = level.origin_x_px - apron_ * b;
  const int y0 = level.origin_y_px - apron_ * b;
  const ClampedSpan columns = clamp_span(x0, span_w, image.width_px);
  const int inside_h = clamp_span(y0, padded_h * b, image.height_px).inside(padded_h * b);
  level.fraction_inside =
      static_cast<float>(static_cast<double>(columns.inside(span_w)) * inside_h /
                         (static_cast<double>(span_w) * padded_h * b));

  // Only the columns [first, end) are read, once per row; columns beyond the image edge are
  // the edge column counted again in the horizontal reduction, so a level wider than the image
  // (a field-covering one with its apron) still reads each source pixel once.
  const int read = columns.end - columns.first;
  const bool rgb = image.format == hal::PixelFormat::kRgb8;
  const int first_byte = columns.first * (rgb ? 3 : 1);
  // Blocks [full_lo, full_hi) lie wholly inside the read columns: the fixed-width reduction.
  const int full_lo = std::min(padded_w, x0 >= columns.first ? 0 : ceil_div(columns.first - x0, b));
  const int full_hi =
      std::clamp(columns.end - x0 >= 0 ? (columns.end - x0) / b : 0, full_lo, padded_w);
  const float norm = 1.0f / static_cast<float>(b * b);
  const auto build_rows = [&](auto* sums) {
    ClampedSpan previous{};
    for (int row = 0; row < padded_h; ++row) {
      float* out = level.samples.data() + static_cast<std::ptrdiff_t>(row) * padded_w;
      const int start = y0 + row * b;
      const ClampedSpan rows = clamp_span(start, b, image.height_px);
      if (row > 0 && rows == previous) {
        // A block row wholly beyond the top or bottom edge repeats the one before it.
        std::copy(out - padded_w, out, out);
        continue;
      }
      previous = rows;
      const int middle_first = std::max(start, rows.first);
      if (rows.inside(b) > 0) {
        sum_rows(sums, image.row(middle_first) + first_byte,
                 static_cast<std::ptrdiff_t>(image.stride_bytes()), rows.inside(b), read, rgb);
      } else {
        std::fill(sums, sums + read, 0u);
      }
      if (rows.before > 0) {
        add_row(sums, image.row(rows.first) + first_byte, read, static_cast<unsigned>(rows.before),
                rgb);
      }
      if (rows.after > 0) {
        add_row(sums, image.row(rows.end - 1) + first_byte, read, static_cast<unsigned>(rows.after),
                rgb);
      }
      if (full_hi > full_lo) {
        reduce_blocks(sums + (x0 + full_lo * b - columns.first), out + full_lo, full_hi - full_lo,
                      b, norm);
      }
      // Blocks reaching past the left or right edge: the edge column's sum once per outside
      // column (replicate), plus the columns inside.
      const auto edge_block = [&](int bx) {
        const int block_start = x0 + bx * b;
        const ClampedSpan c = clamp_span(block_start, b, image.width_px);
        const auto sum_at = [&](int x) -> std::uint32_t { return sums[x - columns.first]; };
        std::uint32_t total = static_cast<std::uint32_t>(c.before) * sum_at(c.first) +
                              static_cast<std::uint32_t>(c.after) * sum_at(c.end - 1);
        const int inside_first = std::max(block_start, c.first);
        for (int x = inside_first; x < inside_first + c.inside(b); ++x) total += sum_at(x);
        out[bx] = static_cast<float>(total) * norm;
      };
      for (int bx = 0; bx < full_lo; ++bx) edge_block(bx);
      for (int bx = full_hi; bx < padded_w; ++bx) edge_block(bx);
    }
  };
  if (b <= kMaxRows16) {
    build_rows(column_sums16_.data());
  } else {
    build_rows(column_sums_.data());
  }
}

RetinaLevelView Retina::level(int k) const {
  const Level& level = levels_[static_cast<std::size_t>(k)];
  RetinaLevelView view;
  view.stride = width_ + 2 * apron_;
  view.interior = level.samples.data() + static_cast<std::ptrdiff_t>(apron_) * view.stride + apron_;
  view.width = width_;
  view.height = height_;
  view.apron = apron_;
  view.scale_px = level.scale_px;
  view.origin_x_px = level.origin_x_px;
  view.origin_y_px = level.origin_y_px;
  view.fraction_inside = level.fraction_inside;
  return view;
}

}  // namespace cambio::perception
