// The retina through a lens: each block of a level is the mean of the ideal (pinhole) image over
// the block, read from the distorted image over the block's footprint there. Footprints and how
// to read them are planned once per scale and origin; a build then only sums pixels.
#include <algorithm>
#include <array>
#include <cmath>
#include <cstring>

#include <immintrin.h>

#include "cambio/perception/retina.hpp"
#include "pixel_sums.hpp"

namespace cambio::perception {

namespace {

using pixel_sums::kMaxRows16;
using pixel_sums::pixel_at;
using pixel_sums::sum_grey;
using pixel_sums::sum_pixels_impl;
using pixel_sums::sum_rows;

// A footprint this many whole rows high or more is summed down its columns first.
constexpr int kRowsSummedDownColumns = 6;
// Runs of grey bytes up to this long are summed inline, longer ones by the vectorised call.
constexpr int kShortRun = 16;

// floor and ceil by truncation (the baseline x86-64 target has no rounding instruction, and
// std::floor is a library call there); |x| < 2^31.
inline int floor_int(double x) {
  const int i = static_cast<int>(x);
  return i - static_cast<int>(x < i);
}
inline int ceil_int(double x) {
  const int i = static_cast<int>(x);
  return i + static_cast<int>(x > i);
}

// A footprint's extent [lo, hi) along one axis (pixel i covers [i, i + 1)) as whole pixels
// [lo_px, hi_px) and the shares `before` of pixel lo_px - 1 and `after` of pixel hi_px (0 where
// they are not covered, so a span ending on a pixel edge never reads past it).
struct Cells {
  int lo_px = 0;
  int hi_px = 0;
  double before = 0.0;
  double after = 0.0;
};

Cells cells_of(double lo, double hi) {
  Cells cells;
  cells.lo_px = ceil_int(lo);
  cells.hi_px = floor_int(hi);
  if (cells.hi_px < cells.lo_px) {  // Within one pixel.
    cells.lo_px = cells.hi_px;
    cells.after = hi - lo;
    return cells;
  }
  cells.before = cells.lo_px - lo;
  cells.after = hi - cells.hi_px;
  return cells;
}

// The sum of the image over the cells xs x ys, all of whose covered pixels are inside it. Tall
// footprints sum their whole rows down the columns first (sum_rows: vector adds in registers, as
// the plain levels do, 64 columns at a time), then weigh the edge columns; short ones go row by
// row.
// The sum of the image over the cells' partial rows (ys.before, ys.after), or over all rows.
template <int kChannels>
double cells_rows_sum(const hal::Image& image, const Cells& xs, const Cells& ys, bool all_rows) {
  const int whole = xs.hi_px - xs.lo_px;
  const auto row_sum = [&](const std::uint8_t* row) {
    double value = 0.0;
    if (xs.before > 0.0) value += xs.before * pixel_at<kChannels>(row, xs.lo_px - 1);
    if (xs.after > 0.0) value += xs.after * pixel_at<kChannels>(row, xs.hi_px);
    if (kChannels == 1 && whole > kShortRun) {
      value += sum_grey(row + xs.lo_px, whole);
    } else {
      value += sum_pixels_impl<kChannels>(row + kChannels * xs.lo_px, whole);
    }
    return value;
  };
  double total = 0.0;
  if (ys.before > 0.0) total += ys.before * row_sum(image.row(ys.lo_px - 1));
  if (ys.after > 0.0) total += ys.after * row_sum(image.row(ys.hi_px));
  if (all_rows) {
    for (int y = ys.lo_px; y < ys.hi_px; ++y) total += row_sum(image.row(y));
  }
  return total;
}

// The cells' columns weighed from their sums down the whole rows (column[x] for column x).
template <typename Sum>
double cells_columns_sum(const Cells& xs, const Sum* column) {
  std::uint32_t whole = 0;
  for (int x = xs.lo_px; x < xs.hi_px; ++x) whole += column[x];
  double total = whole;
  if (xs.before > 0.0) total += xs.before * column[xs.lo_px - 1];
  if (xs.after > 0.0) total += xs.after * column[xs.hi_px];
  return total;
}

// The columns a footprint's cells read, [first, end): the whole ones and the partial ones.
int first_column(const Cells& xs) {
  return xs.before > 0.0 ? xs.lo_px - 1 : xs.lo_px;
}
int end_column(const Cells& xs) {
  return xs.after > 0.0 ? xs.hi_px + 1 : xs.hi_px;
}

// The sum of the image over the cells xs x ys, all of whose covered pixels are inside it. Tall
// footprints sum their whole rows down the columns first (sum_rows: vector adds in registers, as
// the plain levels do, 64 columns at a time), then weigh the edge columns; short ones go row by
// row.
template <int kChannels, typename Sum>
double cells_sum(const hal::Image& image, const Cells& xs, const Cells& ys, Sum* sums) {
  const int rows = ys.hi_px - ys.lo_px;
  if (rows < kRowsSummedDownColumns || sums == nullptr) {
    return cells_rows_sum<kChannels>(image, xs, ys, true);
  }
  const int first = first_column(xs);
  constexpr int kStrip = 64;
  int start = first;
  int count = end_column(xs) - first;
  if (count <= kStrip && image.width_px >= kStrip) {
    start = std::min(first, image.width_px - kStrip);  // A whole strip, still inside the row.
    count = kStrip;
  }
  sum_rows(sums, image.row(ys.lo_px) + kChannels * start,
           static_cast<std::ptrdiff_t>(image.stride_bytes()), rows, count, kChannels == 3);
  return cells_rows_sum<kChannels>(image, xs, ys, false) + cells_columns_sum(xs, sums - start);
}

// The integral over [0, t) of a row or column of n pixels given by its prefix sums (replicating
// the end pixels beyond it): exact for pixels as constant squares, so any span's sum is a
// difference of two of these.
double edge_integral(const std::uint32_t* prefix, int n, double t) {
  if (t <= 0.0) return t * (prefix[1] - prefix[0]);
  if (t >= n) return prefix[n] + (t - n) * (prefix[n] - prefix[n - 1]);
  const int i = floor_int(t);
  return prefix[i] + (t - i) * (prefix[i + 1] - prefix[i]);
}

}  // namespace

void Retina::set_lens(const LensDistortion& lens) {
  set_lens(lens.is_identity()
               ? nullptr
               : std::make_shared<const LensCornerMap>(lens, image_width_px_, image_height_px_));
}

void Retina::set_lens(std::shared_ptr<const LensCornerMap> lens, int plans_per_level) {
  lens_ = lens != nullptr && !lens->is_identity() ? std::move(lens) : nullptr;
  corner_rows_.assign(lens_ ? 4 * static_cast<std::size_t>(width_ + 2 * apron_ + 1) : 0, 0.0);
  const std::size_t blocks = static_cast<std::size_t>(width_ + 2 * apron_) *
                             static_cast<std::size_t>(height_ + 2 * apron_);
  // Column sums for any run of columns in the image, in whole strips of 64 (cells_sum, runs).
  if (lens_) {
    const std::size_t strips = static_cast<std::size_t>(image_width_px_) + 64;
    if (column_sums16_.size() < strips) column_sums16_.resize(strips, 0u);
    if (!column_sums_.empty() && column_sums_.size() < strips) column_sums_.resize(strips, 0u);
  }
  for (auto& level : levels_) {
    level.lens_plans.clear();
    level.lens_plans.resize(lens_ ? static_cast<std::size_t>(std::max(plans_per_level, 1)) : 0);
    for (LensPlan& plan : level.lens_plans) {
      plan.blocks.assign(blocks, LensBlockPlan{});  // Planned at the first build (key 0).
      plan.windows.reserve(blocks);
    }
  }
  const std::size_t column = lens_ ? static_cast<std::size_t>(image_height_px_) + 1 : 0;
  const std::size_t row = lens_ ? static_cast<std::size_t>(image_width_px_) + 1 : 0;
  edge_sums_[0].assign(column, 0u);
  edge_sums_[1].assign(column, 0u);
  edge_sums_[2].assign(row, 0u);
  edge_sums_[3].assign(row, 0u);
}

void Retina::integrate_image_edges(const hal::Image& image) noexcept {
  const int width = image.width_px;
  const int height = image.height_px;
  const bool rgb = image.format == hal::PixelFormat::kRgb8;
  const auto at = [rgb](const std::uint8_t* row, int x) {
    return rgb ? pixel_at<3>(row, x) : pixel_at<1>(row, x);
  };
  for (int y = 0; y < height; ++y) {
    const std::uint8_t* row = image.row(y);
    edge_sums_[0][static_cast<std::size_t>(y) + 1] =
        edge_sums_[0][static_cast<std::size_t>(y)] + at(row, 0);
    edge_sums_[1][static_cast<std::size_t>(y) + 1] =
        edge_sums_[1][static_cast<std::size_t>(y)] + at(row, width - 1);
  }
  const std::uint8_t* top = image.row(0);
  const std::uint8_t* bottom = image.row(height - 1);
  for (int x = 0; x < width; ++x) {
    edge_sums_[2][static_cast<std::size_t>(x) + 1] =
        edge_sums_[2][static_cast<std::size_t>(x)] + at(top, x);
    edge_sums_[3][static_cast<std::size_t>(x) + 1] =
        edge_sums_[3][static_cast<std::size_t>(x)] + at(bottom, x);
  }
  edge_sums_ready_ = true;
}

void Retina::mark_column_runs(LensPlan& level_plan, int blocks_per_row) const noexcept {
  // Neighbours in a block row whose footprints span the same whole rows (most of a row at the
  // image's centre, a few at a time where the lens bends rows) share one pass down their columns.
  const auto tall = [](const LensBlockPlan& plan) {
    const int rows = plan.y_hi - plan.y_lo;
    return plan.kind == LensBlockPlan::Kind::kInside && rows >= kRowsSummedDownColumns &&
           rows <= kMaxRows16;
  };
  const auto columns = [](const LensBlockPlan& plan, bool end) {
    const Cells xs{plan.x_lo, plan.x_hi, plan.x_before, plan.x_after};
    return end ? end_column(xs) : first_column(xs);
  };
  std::vector<LensBlockPlan>& blocks = level_plan.blocks;
  for (std::size_t i = 0; i < blocks.size();) {
    LensBlockPlan& head = blocks[i];
    head.run_end_px = 0;
    if (!tall(head)) {
      ++i;
      continue;
    }
    head.run_first_px = static_cast<std::int16_t>(columns(head, false));
    int end = columns(head, true);
    std::size_t j = i + 1;
    while (j < blocks.size() && j % static_cast<std::size_t>(blocks_per_row) != 0 &&
           tall(blocks[j]) && blocks[j].y_lo == head.y_lo && blocks[j].y_hi == head.y_hi) {
      end = std::max(end, columns(blocks[j], true));
      blocks[j].run_end_px = -1;  // In the run before it.
      ++j;
    }
    head.run_end_px = static_cast<std::int16_t>(end);
    i = j;
  }
}

void Retina::plan_level_through_lens(const hal::Image& image, const Level& level,
                                     LensPlan& level_plan) noexcept {
  using Kind = LensBlockPlan::Kind;
  const int b = level.scale_px;
  const int padded_w = width_ + 2 * apron_;
  const int padded_h = height_ + 2 * apron_;
  const int x0 = level.origin_x_px - apron_ * b;
  const int y0 = level.origin_y_px - apron_ * b;
  const double width = image.width_px;
  const double height = image.height_px;
  // Block corners are pixel corners of the ideal image: looked up, a block row's bottom row of
  // corners becoming the next one's top.
  double* top_corners = corner_rows_.data();
  double* bottom_corners = top_corners + 2 * (padded_w + 1);
  const auto fill_corners = [&](double* corners, int r) {
    for (int c = 0; c <= padded_w; ++c) {
      lens_->corner_px(x0 + c * b, y0 + r * b, corners[2 * c], corners[2 * c + 1]);
    }
  };
  // Far outside the model's valid field a polynomial lens can send points anywhere: kept finite.
  static constexpr double kFar_px = 1e6;
  const auto bounded = [](double x) { return std::clamp(x, -kFar_px, kFar_px); };
  fill_corners(top_corners, 0);
  const bool grey = image.format == hal::PixelFormat::kGrey8;
  double inside = 0.0;
  level_plan.windows.clear();
  LensBlockPlan* plan = level_plan.blocks.data();
  for (int r = 0; r < padded_h; ++r) {
    fill_corners(bottom_corners, r + 1);
    for (int c = 0; c < padded_w; ++c, ++plan) {
      // The block's footprint in the distorted image, as the rectangle through its edges'
      // midpoints (the model is smooth over a block: its corners bend it by far less than a px).
      const double* tl = top_corners + 2 * c;
      const double* bl = bottom_corners + 2 * c;
      const double left = bounded(0.5 * (tl[0] + bl[0]));
      const double right = bounded(0.5 * (tl[2] + bl[2]));
      const double top = bounded(0.5 * (tl[1] + tl[3]));
      const double bottom = bounded(0.5 * (bl[1] + bl[3]));
      *plan = LensBlockPlan{};
      if (!(right > left) || !(bottom > top)) {
        // Folded over by the model (far outside its valid field): the nearest pixel.
        plan->kind = Kind::kNearest;
        plan->x_lo = static_cast<std::int16_t>(
            std::clamp(floor_int(0.5 * (left + right)), 0, image.width_px - 1));
        plan->y_lo = static_cast<std::int16_t>(
            std::clamp(floor_int(0.5 * (top + bottom)), 0, image.height_px - 1));
        continue;
      }
      const double area = (right - left) * (bottom - top);
      const double in_x = std::max(0.0, std::min(right, width) - std::max(left, 0.0));
      const double in_y = std::max(0.0, std::min(bottom, height) - std::max(top, 0.0));
      inside += in_x * in_y / area;
      plan->inverse_area = static_cast<float>(1.0 / area);
      const bool beyond_x = right <= 0.0 || left >= width;
      const bool beyond_y = bottom <= 0.0 || top >= height;
      if (beyond_x && beyond_y) {
        // Off a corner: the corner pixel, replicated.
        plan->kind = Kind::kNearest;
        plan->x_lo = static_cast<std::int16_t>(right <= 0.0 ? 0 : image.width_px - 1);
        plan->y_lo = static_cast<std::int16_t>(bottom <= 0.0 ? 0 : image.height_px - 1);
        continue;
      }
      if (beyond_x || beyond_y) {
        // Beyond one edge: that edge's row or column replicated, over the footprint's span along
        // it (edge 0 left, 1 right, 2 top, 3 bottom, as edge_sums_).
        plan->kind = Kind::kBeyondEdge;
        plan->x_lo =
            static_cast<std::int16_t>(beyond_x ? (right <= 0.0 ? 0 : 1) : (bottom <= 0.0 ? 2 : 3));
        plan->x_before = static_cast<float>(beyond_x ? top : left);
        plan->x_after = static_cast<float>(beyond_x ? bottom : right);
        plan->inverse_area = static_cast<float>(1.0 / (beyond_x ? bottom - top : right - left));
        continue;
      }
      if (!(left >= 0.0 && right <= width && top >= 0.0 && bottom <= height)) {
        plan->kind = Kind::kAtEdge;
        plan->x_before = static_cast<float>(left);
        plan->x_after = static_cast<float>(right);
        plan->y_before = static_cast<float>(top);
        plan->y_after = static_cast<float>(bottom);
        continue;
      }
      const Cells xs = cells_of(left, right);
      const Cells ys = cells_of(top, bottom);
      // A window of 8 x 8 bytes from the cell before the whole ones (inside the image).
      const int x_first = xs.lo_px - 1;
      const int y_first = ys.lo_px - 1;
      const int columns = xs.hi_px - x_first + 1;
      const int rows = ys.hi_px - y_first + 1;
      if (grey && columns <= LensWindow::kSize && rows <= LensWindow::kSize && x_first >= 0 &&
          y_first >= 0 && x_first + LensWindow::kSize <= image.width_px &&
          y_first + rows <= image.height_px) {
        plan->kind = Kind::kWindow;
        // Within the reserved capacity.
        LensWindow& window = level_plan.windows.emplace_back();
        window.sample = static_cast<std::int32_t>(plan - level_plan.blocks.data());
        window.offset =
            static_cast<std::int32_t>(static_cast<std::size_t>(y_first) * image.stride_bytes() +
                                      static_cast<std::size_t>(x_first));
        window.columns = static_cast<std::int16_t>(columns);
        window.rows = static_cast<std::int16_t>(rows);
        window.x_before = static_cast<float>(xs.before);
        window.x_after = static_cast<float>(xs.after);
        window.y_before = static_cast<float>(ys.before);
        window.y_after = static_cast<float>(ys.after);
        window.inverse_area = plan->inverse_area;
        continue;
      }
      plan->kind = Kind::kInside;
      plan->x_lo = static_cast<std::int16_t>(xs.lo_px);
      plan->x_hi = static_cast<std::int16_t>(xs.hi_px);
      plan->y_lo = static_cast<std::int16_t>(ys.lo_px);
      plan->y_hi = static_cast<std::int16_t>(ys.hi_px);
      plan->x_before = static_cast<float>(xs.before);
      plan->x_after = static_cast<float>(xs.after);
      plan->y_before = static_cast<float>(ys.before);
      plan->y_after = static_cast<float>(ys.after);
    }
    std::swap(top_corners, bottom_corners);
  }
  mark_column_runs(level_plan, padded_w);
  level_plan.fraction_inside =
      static_cast<float>(inside / (static_cast<double>(padded_w) * padded_h));
  level_plan.key = {level.scale_px, level.origin_x_px, level.origin_y_px,
                    image.width_px, image.height_px,   static_cast<int>(image.format)};
}

namespace {

// Each window's sample: rows of 8 bytes widened to floats, weighted across (the first and last
// column by their shares, columns past the last by 0) and down, summed in eight lanes and reduced
// once. With AVX2 a row is one widening load and a multiply-add.
static_assert(LensWindow::kSize == 8);

// Eight bytes widened to floats.
__attribute__((target("avx2,fma"))) inline __m256 eight_values(const std::uint8_t* at) {
  return _mm256_cvtepi32_ps(
      _mm256_cvtepu8_epi32(_mm_loadl_epi64(reinterpret_cast<const __m128i*>(at))));
}

__attribute__((target("avx2,fma"))) void read_windows_avx2(const std::uint8_t* __restrict pixels,
                                                           std::ptrdiff_t stride,
                                                           const LensWindow* __restrict windows,
                                                           int count, float* __restrict samples) {
  const __m256 index = _mm256_setr_ps(0.0f, 1.0f, 2.0f, 3.0f, 4.0f, 5.0f, 6.0f, 7.0f);
  const __m256 ones = _mm256_set1_ps(1.0f);
  for (int w = 0; w < count; ++w) {
    const LensWindow& window = windows[w];
    const __m256 last = _mm256_set1_ps(static_cast<float>(window.columns - 1));
    __m256 across = _mm256_and_ps(_mm256_cmp_ps(index, last, _CMP_LT_OQ), ones);
    across = _mm256_blendv_ps(across, _mm256_set1_ps(window.x_after),
                              _mm256_cmp_ps(index, last, _CMP_EQ_OQ));
    across = _mm256_blendv_ps(across, _mm256_set1_ps(window.x_before),
                              _mm256_cmp_ps(index, _mm256_setzero_ps(), _CMP_EQ_OQ));
    const std::uint8_t* row = pixels + window.offset;
    __m256 lanes = _mm256_mul_ps(_mm256_set1_ps(window.y_before), eight_values(row));
    row += stride;
    for (int j = 1; j < window.rows - 1; ++j, row += stride)
      lanes = _mm256_add_ps(lanes, eight_values(row));
    lanes = _mm256_fmadd_ps(_mm256_set1_ps(window.y_after), eight_values(row), lanes);
    lanes = _mm256_mul_ps(lanes, across);
    const __m128 half = _mm_add_ps(_mm256_castps256_ps128(lanes), _mm256_extractf128_ps(lanes, 1));
    const __m128 pairs = _mm_add_ps(half, _mm_movehl_ps(half, half));
    samples[window.sample] =
        window.inverse_area * _mm_cvtss_f32(_mm_add_ss(pairs, _mm_shuffle_ps(pairs, pairs, 1)));
  }
}

void read_windows_scalar(const std::uint8_t* __restrict pixels, std::ptrdiff_t stride,
                         const LensWindow* __restrict windows, int count,
                         float* __restrict samples) {
  for (int w = 0; w < count; ++w) {
    const LensWindow& window = windows[w];
    const auto row_sum = [&](const std::uint8_t* row) {
      float whole = 0.0f;
      for (int i = 1; i < window.columns - 1; ++i) whole += row[i];
      return window.x_before * row[0] + whole + window.x_after * row[window.columns - 1];
    };
    const std::uint8_t* row = pixels + window.offset;
    float sample = window.y_before * row_sum(row);
    row += stride;
    for (int j = 1; j < window.rows - 1; ++j, row += stride) sample += row_sum(row);
    sample += window.y_after * row_sum(row);
    samples[window.sample] = window.inverse_area * sample;
  }
}

void read_windows(const std::uint8_t* pixels, std::ptrdiff_t stride, const LensWindow* windows,
                  int count, float* samples) {
  static const bool avx2 = __builtin_cpu_supports("avx2") && __builtin_cpu_supports("fma");
  if (avx2) {
    read_windows_avx2(pixels, stride, windows, count, samples);
  } else {
    read_windows_scalar(pixels, stride, windows, count, samples);
  }
}

}  // namespace

template <int kChannels>
double Retina::footprint_sum(const hal::Image& image, const LensBlockPlan& plan) noexcept {
  const auto cells = [&](const Cells& xs, const Cells& ys) {
    if (ys.hi_px - ys.lo_px <= kMaxRows16)
      return cells_sum<kChannels>(image, xs, ys, column_sums16_.data());
    std::uint32_t* sums = column_sums_.empty() ? nullptr : column_sums_.data();
    return cells_sum<kChannels>(image, xs, ys, sums);
  };
  if (plan.kind == LensBlockPlan::Kind::kInside) {
    return cells(Cells{plan.x_lo, plan.x_hi, plan.x_before, plan.x_after},
                 Cells{plan.y_lo, plan.y_hi, plan.y_before, plan.y_after});
  }
  // At the image's edges: the part inside, plus what lies beyond each edge, which is the edge
  // row or column replicated (the retina's border policy), from their prefix sums. The left and
  // right parts take the corners.
  if (!edge_sums_ready_) integrate_image_edges(image);
  const double left = plan.x_before;
  const double right = plan.x_after;
  const double top = plan.y_before;
  const double bottom = plan.y_after;
  const int width = image.width_px;
  const int height = image.height_px;
  const double in_left = std::clamp(left, 0.0, static_cast<double>(width));
  const double in_right = std::clamp(right, 0.0, static_cast<double>(width));
  const double in_top = std::clamp(top, 0.0, static_cast<double>(height));
  const double in_bottom = std::clamp(bottom, 0.0, static_cast<double>(height));
  double total = 0.0;
  if (in_right > in_left && in_bottom > in_top) {
    total += cells(cells_of(in_left, in_right), cells_of(in_top, in_bottom));
  }
  const auto along = [&](int edge, int n, double lo, double hi) {
    const std::uint32_t* prefix = edge_sums_[static_cast<std::size_t>(edge)].data();
    return edge_integral(prefix, n, hi) - edge_integral(prefix, n, lo);
  };
  if (left < 0.0) total += (std::min(right, 0.0) - left) * along(0, height, top, bottom);
  if (right > width)
    total += (right - std::max(left, static_cast<double>(width))) * along(1, height, top, bottom);
  if (in_right > in_left) {
    if (top < 0.0) total += (std::min(bottom, 0.0) - top) * along(2, width, in_left, in_right);
    if (bottom > height)
      total += (bottom - std::max(top, static_cast<double>(height))) *
               along(3, width, in_left, in_right);
  }
  return total;
}

void Retina::build_level_through_lens(const hal::Image& image, Level& level) noexcept {
  using Kind = LensBlockPlan::Kind;
  const std::array<int, 6> key{level.scale_px, level.origin_x_px, level.origin_y_px,
                               image.width_px, image.height_px,   static_cast<int>(image.format)};
  // The plan for this place, else the least recently used one replanned.
  LensPlan* level_plan = &level.lens_plans.front();
  for (LensPlan& candidate : level.lens_plans) {
    if (candidate.key == key) {
      level_plan = &candidate;
      break;
    }
    if (candidate.last_used < level_plan->last_used) level_plan = &candidate;
  }
  if (level_plan->key != key) plan_level_through_lens(image, level, *level_plan);
  level_plan->last_used = ++lens_builds_;
  level.fraction_inside = level_plan->fraction_inside;
  const bool rgb = image.format == hal::PixelFormat::kRgb8;
  read_windows(image.pixels.data(), static_cast<std::ptrdiff_t>(image.stride_bytes()),
               level_plan->windows.data(), static_cast<int>(level_plan->windows.size()),
               level.samples.data());
  float* out = level.samples.data();
  const std::uint16_t* run_columns = nullptr;  // The current run's column sums, by column.
  for (const LensBlockPlan& plan : level_plan->blocks) {
    switch (plan.kind) {
      case Kind::kWindow:
        break;  // Read above.
      case Kind::kInside:
        if (plan.run_end_px != 0) {
          if (plan.run_end_px > 0) {
            // Whole strips of 64 columns (summed in registers), moved left to stay in the row.
            const int count = (plan.run_end_px - plan.run_first_px + 63) / 64 * 64;
            const int start = count <= image.width_px
                                  ? std::min<int>(plan.run_first_px, image.width_px - count)
                                  : plan.run_first_px;
            sum_rows(column_sums16_.data(), image.row(plan.y_lo) + (rgb ? 3 : 1) * start,
                     static_cast<std::ptrdiff_t>(image.stride_bytes()), plan.y_hi - plan.y_lo,
                     count <= image.width_px ? count : plan.run_end_px - start, rgb);
            run_columns = column_sums16_.data() - start;
          }
          const Cells xs{plan.x_lo, plan.x_hi, plan.x_before, plan.x_after};
          const Cells ys{plan.y_lo, plan.y_hi, plan.y_before, plan.y_after};
          const double rows = rgb ? cells_rows_sum<3>(image, xs, ys, false)
                                  : cells_rows_sum<1>(image, xs, ys, false);
          *out =
              static_cast<float>((rows + cells_columns_sum(xs, run_columns)) * plan.inverse_area);
          break;
        }
        [[fallthrough]];
      case Kind::kAtEdge:
        *out = static_cast<float>(
            (rgb ? footprint_sum<3>(image, plan) : footprint_sum<1>(image, plan)) *
            plan.inverse_area);
        break;
      case Kind::kBeyondEdge: {
        if (!edge_sums_ready_) integrate_image_edges(image);
        const int edge = plan.x_lo;
        const std::uint32_t* prefix = edge_sums_[static_cast<std::size_t>(edge)].data();
        const int n = edge < 2 ? image.height_px : image.width_px;
        *out = static_cast<float>(
            (edge_integral(prefix, n, plan.x_after) - edge_integral(prefix, n, plan.x_before)) *
            plan.inverse_area);
        break;
      }
      case Kind::kNearest:
        *out = static_cast<float>(rgb ? pixel_at<3>(image.row(plan.y_lo), plan.x_lo)
                                      : pixel_at<1>(image.row(plan.y_lo), plan.x_lo));
        break;
    }
    ++out;
  }
}

}  // namespace cambio::perception
