#include "cambio/perception/retina.hpp"

#include <algorithm>
#include <stdexcept>

#include "cambio/hal/luma.hpp"

namespace cambio::perception {

namespace {

void rgb_row_to_grey(const std::uint8_t* rgb, std::uint8_t* grey, int width) {
  for (int x = 0; x < width; ++x) {
    grey[x] = hal::luma_bt601(rgb[3 * x], rgb[3 * x + 1], rgb[3 * x + 2]);
  }
}

__attribute__((target_clones("avx2", "default"))) void add_row(std::uint32_t* __restrict sums,
                                                               const std::uint8_t* __restrict row,
                                                               int count) {
  for (int i = 0; i < count; ++i) sums[i] += row[i];
}

__attribute__((target_clones("avx2", "default"))) void add_row(std::uint16_t* __restrict sums,
                                                               const std::uint8_t* __restrict row,
                                                               int count) {
  for (int i = 0; i < count; ++i) sums[i] = static_cast<std::uint16_t>(sums[i] + row[i]);
}

template <typename Sum>
void add_row_gathered(Sum* __restrict sums, const std::uint8_t* __restrict row,
                      const std::int32_t* __restrict index, int count) {
  for (int i = 0; i < count; ++i) sums[i] = static_cast<Sum>(sums[i] + row[index[i]]);
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
  column_sums_.assign(padded_w * static_cast<std::size_t>(max_scale_), 0u);
  column_sums16_.assign(padded_w * static_cast<std::size_t>(std::min(max_scale_, 16)), 0u);
  column_index_.assign(padded_w * static_cast<std::size_t>(max_scale_), 0);
  luma_row_.assign(static_cast<std::size_t>(std::max(image_width_px, 1)), 0u);
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

hal::Status Retina::build(const hal::Image& image, PixelPoint fixation) noexcept {
  if (image.empty() || image.width_px <= 0 || image.height_px <= 0) return hal::Status::kRejected;
  if (image.format == hal::PixelFormat::kRgb8 &&
      static_cast<std::size_t>(image.width_px) > luma_row_.size()) {
    return hal::Status::kRejected;
  }
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
  if (image.format == hal::PixelFormat::kRgb8 &&
      static_cast<std::size_t>(image.width_px) > luma_row_.size()) {
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
  const int b = level.scale_px;
  const int padded_w = width_ + 2 * apron_;
  const int padded_h = height_ + 2 * apron_;
  const int span_w = padded_w * b;  // Source columns under the level, apron included.
  const int x0 = level.origin_x_px - apron_ * b;
  const int y0 = level.origin_y_px - apron_ * b;
  const bool columns_inside = x0 >= 0 && x0 + span_w <= image.width_px;
  if (!columns_inside) {
    for (int j = 0; j < span_w; ++j) {
      column_index_[static_cast<std::size_t>(j)] = std::clamp(x0 + j, 0, image.width_px - 1);
    }
  }
  const int inside_w = std::max(0, std::min(x0 + span_w, image.width_px) - std::max(x0, 0));
  const int inside_h = std::max(0, std::min(y0 + padded_h * b, image.height_px) - std::max(y0, 0));
  level.fraction_inside = static_cast<float>(static_cast<double>(inside_w) * inside_h /
                                             (static_cast<double>(span_w) * padded_h * b));

  const bool rgb = image.format == hal::PixelFormat::kRgb8;
  const float norm = 1.0f / static_cast<float>(b * b);
  const auto sum_rows = [&](auto* sums) {
    for (int row = 0; row < padded_h; ++row) {
      std::fill(sums, sums + span_w, 0u);
      for (int dy = 0; dy < b; ++dy) {
        const int sy = std::clamp(y0 + row * b + dy, 0, image.height_px - 1);
        const std::uint8_t* src = image.row(sy);
        if (rgb) {
          rgb_row_to_grey(src, luma_row_.data(), image.width_px);
          src = luma_row_.data();
        }
        if (columns_inside) {
          add_row(sums, src + x0, span_w);
        } else {
          add_row_gathered(sums, src, column_index_.data(), span_w);
        }
      }
      reduce_blocks(sums, level.samples.data() + static_cast<std::ptrdiff_t>(row) * padded_w,
                    padded_w, b, norm);
    }
  };
  // Exact either way: a column sum of b <= 16 bytes fits 16 bits.
  if (b <= 16) {
    sum_rows(column_sums16_.data());
  } else {
    sum_rows(column_sums_.data());
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
