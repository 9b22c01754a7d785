#include "cambio/perception/retina.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <stdexcept>

#include "cambio/hal/luma.hpp"

namespace cambio::perception {

namespace {

// Adds `weight` times one source row to the column sums: grey pixels as they are, rgb8 pixels
// through hal::luma_bt601, so only the pixels a level reads are converted, inside the sum, and a
// colour frame gives exactly the levels of its grey conversion. The weight of a replicated edge
// row is the count of rows beyond the edge that map onto it.
template <typename Sum>
[[gnu::always_inline]] inline void accumulate_row(Sum* __restrict sums,
                                                  const std::uint8_t* __restrict row, int count,
                                                  unsigned weight, bool rgb) {
  if (rgb) {
    if (weight == 1) {
      for (int i = 0; i < count; ++i) {
        sums[i] =
            static_cast<Sum>(sums[i] + hal::luma_bt601(row[3 * i], row[3 * i + 1], row[3 * i + 2]));
      }
    } else {
      for (int i = 0; i < count; ++i) {
        sums[i] = static_cast<Sum>(
            sums[i] + weight * hal::luma_bt601(row[3 * i], row[3 * i + 1], row[3 * i + 2]));
      }
    }
  } else if (weight == 1) {
    for (int i = 0; i < count; ++i) sums[i] = static_cast<Sum>(sums[i] + row[i]);
  } else {
    for (int i = 0; i < count; ++i) sums[i] = static_cast<Sum>(sums[i] + weight * row[i]);
  }
}

__attribute__((target_clones("avx2", "default"))) void add_row(std::uint32_t* __restrict sums,
                                                               const std::uint8_t* __restrict row,
                                                               int count, unsigned weight,
                                                               bool rgb) {
  accumulate_row(sums, row, count, weight, rgb);
}

__attribute__((target_clones("avx2", "default"))) void add_row(std::uint16_t* __restrict sums,
                                                               const std::uint8_t* __restrict row,
                                                               int count, unsigned weight,
                                                               bool rgb) {
  accumulate_row(sums, row, count, weight, rgb);
}

// Sets sums[i] to the sum over `rows` rows (from `top`, `stride` bytes apart) of pixel i, grey or
// through hal::luma_bt601: one call per block row, each strip of columns summed down all rows
// while its sums stay in registers, so a tall block (a field-covering level's 40 rows at
// 640 x 480) costs a load and an add per pixel, not a row call and a store.
template <typename Sum, int kChannels>
[[gnu::always_inline]] inline void sum_rows_impl(Sum* __restrict sums,
                                                 const std::uint8_t* __restrict top,
                                                 std::ptrdiff_t stride, int rows, int count) {
  const auto pixel = [](const std::uint8_t* p, int i) -> unsigned {
    if constexpr (kChannels == 3) {
      return hal::luma_bt601(p[3 * i], p[3 * i + 1], p[3 * i + 2]);
    } else {
      return p[i];
    }
  };
  constexpr int kStrip = 64;
  int x = 0;
  for (; x + kStrip <= count; x += kStrip) {
    Sum acc[kStrip] = {};
    const std::uint8_t* p = top + static_cast<std::ptrdiff_t>(x) * kChannels;
    for (int y = 0; y < rows; ++y, p += stride) {
      for (int i = 0; i < kStrip; ++i) acc[i] = static_cast<Sum>(acc[i] + pixel(p, i));
    }
    for (int i = 0; i < kStrip; ++i) sums[x + i] = acc[i];
  }
  if (x == count) return;
  std::fill(sums + x, sums + count, Sum{0});
  const std::uint8_t* p = top + static_cast<std::ptrdiff_t>(x) * kChannels;
  for (int y = 0; y < rows; ++y, p += stride) {
    for (int i = 0; i < count - x; ++i) sums[x + i] = static_cast<Sum>(sums[x + i] + pixel(p, i));
  }
}

__attribute__((target_clones("avx2", "default"))) void sum_rows(std::uint32_t* __restrict sums,
                                                                const std::uint8_t* __restrict top,
                                                                std::ptrdiff_t stride, int rows,
                                                                int count, bool rgb) {
  if (rgb) {
    sum_rows_impl<std::uint32_t, 3>(sums, top, stride, rows, count);
  } else {
    sum_rows_impl<std::uint32_t, 1>(sums, top, stride, rows, count);
  }
}

__attribute__((target_clones("avx2", "default"))) void sum_rows(std::uint16_t* __restrict sums,
                                                                const std::uint8_t* __restrict top,
                                                                std::ptrdiff_t stride, int rows,
                                                                int count, bool rgb) {
  if (rgb) {
    sum_rows_impl<std::uint16_t, 3>(sums, top, stride, rows, count);
  } else {
    sum_rows_impl<std::uint16_t, 1>(sums, top, stride, rows, count);
  }
}

// A compile-time block width: the block sum is a fixed run of adds the compiler turns into
// whole-vector loads and a short horizontal reduction instead of a counted inner loop.
template <int kScale, typename Sum>
[[gnu::always_inline]] inline void reduce_fixed(const Sum* __restrict sums, float* __restrict out,
                                                int count, float norm) {
  for (int i = 0; i < count; ++i) {
    std::uint32_t total = 0;
    const Sum* block = sums + static_cast<std::ptrdiff_t>(i) * kScale;
    for (int j = 0; j < kScale; ++j) total += block[j];
    out[i] = static_cast<float>(total) * norm;
  }
}

template <typename Sum>
[[gnu::always_inline]] inline void reduce_any(const Sum* __restrict sums, float* __restrict out,
                                              int count, int scale, float norm) {
  switch (scale) {
    case 1:
      for (int i = 0; i < count; ++i) out[i] = static_cast<float>(sums[i]) * norm;
      return;
    case 2:
      reduce_fixed<2>(sums, out, count, norm);
      return;
    case 4:
      reduce_fixed<4>(sums, out, count, norm);
      return;
    case 8:
      reduce_fixed<8>(sums, out, count, norm);
      return;
    case 16:
      reduce_fixed<16>(sums, out, count, norm);
      return;
    default:
      break;
  }
  for (int i = 0; i < count; ++i) {
    std::uint32_t total = 0;
    const Sum* block = sums + static_cast<std::ptrdiff_t>(i) * scale;
    for (int j = 0; j < scale; ++j) total += block[j];
    out[i] = static_cast<float>(total) * norm;
  }
}

__attribute__((target_clones("avx2", "default"))) void reduce_blocks(
    const std::uint32_t* __restrict sums, float* __restrict out, int count, int scale, float norm) {
  reduce_any(sums, out, count, scale, norm);
}

__attribute__((target_clones("avx2", "default"))) void reduce_blocks(
    const std::uint16_t* __restrict sums, float* __restrict out, int count, int scale, float norm) {
  reduce_any(sums, out, count, scale, norm);
}

int ceil_div(int a, int b) {
  return (a + b - 1) / b;
}

// A column sum of b rows of bytes fits 16 bits while b * 255 < 2^16: twice the lanes per add.
constexpr int kMaxScale16 = 257;

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

// Through a lens: the weights with which pixels [0, size) cover the span [lo, hi) of pixel-edge
// coordinates (pixel i covers [i, i + 1)): whole pixels [full_lo, full_hi) with weight 1, and up
// to four others with the share they cover; beyond the edges the edge pixel, once per unit of
// span out there (replicate, as the retina's border policy).
struct SpanWeights {
  int full_lo = 0;
  int full_hi = 0;
  std::array<int, 4> index{};
  std::array<double, 4> weight{};
  int extras = 0;
  void add(int i, double w) {
    if (!(w > 0.0)) return;
    index[static_cast<std::size_t>(extras)] = i;
    weight[static_cast<std::size_t>(extras)] = w;
    ++extras;
  }
};

SpanWeights span_weights(double lo, double hi, int size) {
  SpanWeights span;
  const double end = static_cast<double>(size);
  span.add(0, std::min(hi, 0.0) - lo);
  span.add(size - 1, hi - std::max(lo, end));
  const double a = std::max(lo, 0.0);
  const double c = std::min(hi, end);
  if (!(a < c)) return span;
  const int first = static_cast<int>(std::floor(a));
  const int last = std::min(static_cast<int>(std::floor(c)), size - 1);
  if (first == last) {
    span.add(first, c - a);
    return span;
  }
  span.full_lo = static_cast<int>(std::ceil(a));
  span.full_hi = static_cast<int>(std::floor(c));
  if (a < span.full_lo) span.add(first, span.full_lo - a);
  if (c > span.full_hi && span.full_hi < size) span.add(span.full_hi, c - span.full_hi);
  return span;
}

template <int kChannels>
inline unsigned pixel_at(const std::uint8_t* row, int x) {
  if constexpr (kChannels == 3) {
    return hal::luma_bt601(row[3 * x], row[3 * x + 1], row[3 * x + 2]);
  } else {
    return row[x];
  }
}

// The sum of n pixels from p: grey bytes in fixed runs of 32 the compiler vectorises (a counted
// loop of unknown length it leaves scalar at -O2), or luma through hal::luma_bt601.
template <int kChannels>
[[gnu::always_inline]] inline std::uint32_t sum_pixels_impl(const std::uint8_t* __restrict p,
                                                            int n) {
  std::uint32_t total = 0;
  int i = 0;
  if constexpr (kChannels == 1) {
    constexpr int kRun = 32;
    for (; i + kRun <= n; i += kRun) {
      std::uint32_t run = 0;
      for (int j = 0; j < kRun; ++j) run += p[i + j];
      total += run;
    }
  }
  for (; i < n; ++i) total += pixel_at<kChannels>(p, i);
  return total;
}

__attribute__((target_clones("avx2", "default"))) std::uint32_t sum_grey(
    const std::uint8_t* __restrict p, int n) {
  return sum_pixels_impl<1>(p, n);
}

template <int kChannels>
double row_value(const std::uint8_t* row, const SpanWeights& columns) {
  const int n = columns.full_hi - columns.full_lo;
  double value = 0.0;
  if (n > 0) {
    value = kChannels == 1 ? sum_grey(row + columns.full_lo, n)
                           : sum_pixels_impl<kChannels>(row + kChannels * columns.full_lo, n);
  }
  for (int i = 0; i < columns.extras; ++i) {
    const auto at = static_cast<std::size_t>(i);
    value += columns.weight[at] * pixel_at<kChannels>(row, columns.index[at]);
  }
  return value;
}

// The mean of the image over [left, right) x [top, bottom) (pixel-edge coordinates), partial
// pixels by the share they cover, the edge pixels beyond the edges.
template <int kChannels>
float box_mean(const hal::Image& image, double left, double right, double top, double bottom) {
  if (!(right > left) || !(bottom > top)) {
    // A footprint the lens model folds over (far outside its valid field): the nearest pixel.
    const int x =
        std::clamp(static_cast<int>(std::floor(0.5 * (left + right))), 0, image.width_px - 1);
    const int y =
        std::clamp(static_cast<int>(std::floor(0.5 * (top + bottom))), 0, image.height_px - 1);
    return static_cast<float>(pixel_at<kChannels>(image.row(y), x));
  }
  if (std::abs(right - left - 1.0) < 0.05 && std::abs(bottom - top - 1.0) < 0.05 && left >= 0.0 &&
      top >= 0.0 && right < image.width_px - 1 && bottom < image.height_px - 1) {
    // A pixel-sized footprint (level 0) inside the image: the mean over a unit box at any offset
    // is the bilinear interpolation at its centre, four reads.
    const int x = static_cast<int>(std::floor(left + 0.5 * (right - left) - 0.5));
    const int y = static_cast<int>(std::floor(top + 0.5 * (bottom - top) - 0.5));
    const double fx = left + 0.5 * (right - left) - 0.5 - x;
    const double fy = top + 0.5 * (bottom - top) - 0.5 - y;
    const std::uint8_t* r0 = image.row(y);
    const std::uint8_t* r1 = image.row(y + 1);
    const double upper =
        (1.0 - fx) * pixel_at<kChannels>(r0, x) + fx * pixel_at<kChannels>(r0, x + 1);
    const double lower =
        (1.0 - fx) * pixel_at<kChannels>(r1, x) + fx * pixel_at<kChannels>(r1, x + 1);
    return static_cast<float>((1.0 - fy) * upper + fy * lower);
  }
  const SpanWeights columns = span_weights(left, right, image.width_px);
  const SpanWeights rows = span_weights(top, bottom, image.height_px);
  double total = 0.0;
  for (int y = rows.full_lo; y < rows.full_hi; ++y) {
    total += row_value<kChannels>(image.row(y), columns);
  }
  for (int i = 0; i < rows.extras; ++i) {
    const auto at = static_cast<std::size_t>(i);
    total += rows.weight[at] * row_value<kChannels>(image.row(rows.index[at]), columns);
  }
  return static_cast<float>(total / ((right - left) * (bottom - top)));
}

}  // namespace

Retina::Retina(const RetinaConfig& config, int apron_px, int image_width_px, int image_height_px)
    : config_(config), width_(config.width_px), height_(config.height_px), apron_(apron_px) {
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
  column_sums16_.assign(padded_w * static_cast<std::size_t>(std::min(max_scale_, kMaxScale16)), 0u);
  if (max_scale_ > kMaxScale16) {
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

void Retina::set_lens(const LensDistortion& lens) {
  lens_ = lens;
  const std::size_t corners = static_cast<std::size_t>(width_ + 2 * apron_ + 1) *
                              static_cast<std::size_t>(height_ + 2 * apron_ + 1);
  for (auto& level : levels_) {
    level.corners_px.assign(lens_.is_identity() ? 0 : 2 * corners, 0.0);
    level.corners_scale_px = 0;  // Computed at the first build.
  }
}

hal::Status Retina::build(const hal::Image& image, PixelPoint fixation) noexcept {
  if (image.empty() || image.width_px <= 0 || image.height_px <= 0) return hal::Status::kRejected;
  fixation_ = fixation;
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
  if (image.empty() || image.width_px <= 0 || image.height_px <= 0 || k < 0 || k >= levels()) {
    return hal::Status::kRejected;
  }
  Level& level = levels_[static_cast<std::size_t>(k)];
  level.scale_px = scale_of(k, image.width_px, image.height_px, fixation);
  level.origin_x_px = fixation.x - (width_ / 2) * level.scale_px;
  level.origin_y_px = fixation.y - (height_ / 2) * level.scale_px;
  build_level(image, level);
  return hal::Status::kOk;
}

void Retina::build_level(const hal::Image& image, Level& level) noexcept {
  if (!lens_.is_identity()) {
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
  if (b <= kMaxScale16) {
    build_rows(column_sums16_.data());
  } else {
    build_rows(column_sums_.data());
  }
}

void Retina::build_level_through_lens(const hal::Image& image, Level& level) noexcept {
  const int b = level.scale_px;
  const int padded_w = width_ + 2 * apron_;
  const int padded_h = height_ + 2 * apron_;
  const int corners_w = padded_w + 1;
  const int x0 = level.origin_x_px - apron_ * b;
  const int y0 = level.origin_y_px - apron_ * b;
  if (level.corners_scale_px != b || level.corners_origin_x_px != level.origin_x_px ||
      level.corners_origin_y_px != level.origin_y_px) {
    // Each block corner of the ideal image, through the lens (pixel-edge coordinates in and out;
    // the model takes pixel centres): once per scale and origin, a few thousand evaluations.
    for (int r = 0; r <= padded_h; ++r) {
      for (int c = 0; c <= padded_w; ++c) {
        double u = 0.0;
        double v = 0.0;
        lens_.distort_px(x0 + c * b - 0.5, y0 + r * b - 0.5, u, v);
        double* corner =
            level.corners_px.data() + 2 * (static_cast<std::ptrdiff_t>(r) * corners_w + c);
        corner[0] = u + 0.5;
        corner[1] = v + 0.5;
      }
    }
    level.corners_scale_px = b;
    level.corners_origin_x_px = level.origin_x_px;
    level.corners_origin_y_px = level.origin_y_px;
  }
  const bool rgb = image.format == hal::PixelFormat::kRgb8;
  const double width = image.width_px;
  const double height = image.height_px;
  double inside = 0.0;
  for (int r = 0; r < padded_h; ++r) {
    float* out = level.samples.data() + static_cast<std::ptrdiff_t>(r) * padded_w;
    for (int c = 0; c < padded_w; ++c) {
      // The block's footprint in the distorted image, as the rectangle through its edges'
      // midpoints (the model is smooth over a block: its corners bend it by far less than a px).
      const double* tl =
          level.corners_px.data() + 2 * (static_cast<std::ptrdiff_t>(r) * corners_w + c);
      const double* tr = tl + 2;
      const double* bl = tl + 2 * corners_w;
      const double* br = bl + 2;
      const double left = 0.5 * (tl[0] + bl[0]);
      const double right = 0.5 * (tr[0] + br[0]);
      const double top = 0.5 * (tl[1] + tr[1]);
      const double bottom = 0.5 * (bl[1] + br[1]);
      out[c] = rgb ? box_mean<3>(image, left, right, top, bottom)
                   : box_mean<1>(image, left, right, top, bottom);
      const double area = (right - left) * (bottom - top);
      if (area > 0.0) {
        const double in_x = std::max(0.0, std::min(right, width) - std::max(left, 0.0));
        const double in_y = std::max(0.0, std::min(bottom, height) - std::max(top, 0.0));
        inside += in_x * in_y / area;
      }
    }
  }
  level.fraction_inside = static_cast<float>(inside / (static_cast<double>(padded_w) * padded_h));
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
