#include "cambio/perception/fixated_region.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace cambio::perception {

ZeroDisparityFilter::ZeroDisparityFilter(const FixatedRegionConfig& config)
    : config_(config),
      cells_(config.cells),
      cell_px_(config.cell_px),
      shift_px_(config.max_disparity_px),
      span_px_(config.cells * config.cell_px) {
  left_grey_.assign(static_cast<std::size_t>(cell_px_) * cell_px_, 0.0f);
  right_grey_.assign(static_cast<std::size_t>(cell_px_ + 2 * shift_px_) * cell_px_, 0.0f);
  classes_.assign(static_cast<std::size_t>(cells_) * cells_, Cell::kUnread);
  region_.assign(classes_.size(), 0);
  stack_.assign(classes_.size(), 0);
}

void ZeroDisparityFilter::read_grey(const hal::Image& image, int x0, int y0, int width, int height,
                                    std::vector<float>& out) noexcept {
  const int channels = image.channels();
  const float norm = 1.0f / static_cast<float>(channels);
  for (int y = 0; y < height; ++y) {
    float* row_out = out.data() + static_cast<std::ptrdiff_t>(y) * width;
    const int source_y = y0 + y;
    if (source_y < 0 || source_y >= image.height_px) {
      std::fill(row_out, row_out + width, std::numeric_limits<float>::quiet_NaN());
      continue;
    }
    const std::uint8_t* row = image.row(source_y);
    for (int x = 0; x < width; ++x) {
      const int source_x = x0 + x;
      if (source_x < 0 || source_x >= image.width_px) {
        row_out[x] = std::numeric_limits<float>::quiet_NaN();
        continue;
      }
      const std::uint8_t* pixel = row + static_cast<std::ptrdiff_t>(source_x) * channels;
      int sum = 0;
      for (int c = 0; c < channels; ++c) sum += pixel[c];
      row_out[x] = static_cast<float>(sum) * norm;
    }
  }
}

ZeroDisparityFilter::Cell ZeroDisparityFilter::cell(int column, int row) noexcept {
  Cell& known = classes_[static_cast<std::size_t>(row * cells_ + column)];
  if (known == Cell::kUnread) known = classify(column, row);
  return known;
}

ZeroDisparityFilter::Cell ZeroDisparityFilter::classify(int column, int row) noexcept {
  const int n = cell_px_ * cell_px_;
  const int right_width = cell_px_ + 2 * shift_px_;
  const int half = span_px_ / 2;
  read_grey(*left_, left_fixation_.x - half + column * cell_px_,
            left_fixation_.y - half + row * cell_px_, cell_px_, cell_px_, left_grey_);
  read_grey(*right_, right_fixation_.x - half + column * cell_px_ - shift_px_,
            right_fixation_.y - half + row * cell_px_, right_width, cell_px_, right_grey_);
  const float* left = left_grey_.data();
  float sum = 0.0f, sum_squares = 0.0f;
  for (int y = 0; y < cell_px_; ++y) {
    for (int x = 0; x < cell_px_; ++x) {
      const float v = left[y * cell_px_ + x];
      sum += v;
      sum_squares += v * v;
    }
  }
  if (!std::isfinite(sum)) return Cell::kOutside;
  const float mean = sum / static_cast<float>(n);
  const float left_energy = sum_squares - sum * mean;
  const float min_energy = static_cast<float>(config_.min_texture_grey * config_.min_texture_grey) *
                           static_cast<float>(n);
  bool textured_right = false;
  float best = -1.0f;
  for (int shift = -shift_px_; shift <= shift_px_; ++shift) {
    const float* right = right_grey_.data() + shift_px_ + shift;
    float r_sum = 0.0f, r_squares = 0.0f, cross = 0.0f;
    for (int y = 0; y < cell_px_; ++y) {
      for (int x = 0; x < cell_px_; ++x) {
        const float l = left[y * cell_px_ + x];
        const float r = right[y * right_width + x];
        r_sum += r;
        r_squares += r * r;
        cross += l * r;
      }
    }
    if (!std::isfinite(r_sum)) return Cell::kOutside;
    const float right_energy = r_squares - r_sum * r_sum / static_cast<float>(n);
    if (right_energy < min_energy) continue;
    textured_right = true;
    if (left_energy < min_energy) continue;
    const float zncc =
        (cross - sum * r_sum / static_cast<float>(n)) / std::sqrt(left_energy * right_energy);
    best = std::max(best, zncc);
  }
  if (left_energy < min_energy && !textured_right) return Cell::kFlat;
  return best >= static_cast<float>(config_.min_correlation) ? Cell::kMatch : Cell::kMismatch;
}

void ZeroDisparityFilter::find(const hal::Image& left, PixelPoint left_fixation,
                               const hal::Image& right, PixelPoint right_fixation,
                               FixatedRegion& out) noexcept {
  out = FixatedRegion{};
  const int half = span_px_ / 2;
  left_ = &left;
  right_ = &right;
  left_fixation_ = left_fixation;
  right_fixation_ = right_fixation;
  std::fill(classes_.begin(), classes_.end(), Cell::kUnread);
  std::fill(region_.begin(), region_.end(), std::uint8_t{0});

  // The seed: the matching cell nearest the fixation (the cell holding it, then rings).
  const int centre = cells_ / 2;
  int seed = -1;
  for (int ring = 0; ring <= config_.seed_radius_cells && seed < 0; ++ring) {
    int best_distance = std::numeric_limits<int>::max();
    for (int row = centre - ring; row <= centre + ring; ++row) {
      for (int column = centre - ring; column <= centre + ring; ++column) {
        if (row < 0 || row >= cells_ || column < 0 || column >= cells_) continue;
        if (std::max(std::abs(row - centre), std::abs(column - centre)) != ring) continue;
        if (cell(column, row) != Cell::kMatch) continue;
        const int distance =
            (row - centre) * (row - centre) + (column - centre) * (column - centre);
        if (distance < best_distance) {
          best_distance = distance;
          seed = row * cells_ + column;
        }
      }
    }
  }
  if (seed < 0) return;

  // Flood fill through 8-neighbours, the stack sized for every cell.
  std::size_t top = 0;
  stack_[top++] = seed;
  region_[static_cast<std::size_t>(seed)] = 1;
  double sum_x = 0.0, sum_y = 0.0;
  int count = 0, min_column = cells_, max_column = -1, min_row = cells_, max_row = -1;
  while (top > 0) {
    const int index = stack_[--top];
    const int row = index / cells_;
    const int column = index % cells_;
    ++count;
    sum_x += column;
    sum_y += row;
    min_column = std::min(min_column, column);
    max_column = std::max(max_column, column);
    min_row = std::min(min_row, row);
    max_row = std::max(max_row, row);
    // At the window's edge the region is cut (a wall, an object larger than the window): its
    // centre is not the object's, and growing it further would only cost.
    if (row == 0 || column == 0 || row == cells_ - 1 || column == cells_ - 1) break;
    for (int dy = -1; dy <= 1; ++dy) {
      for (int dx = -1; dx <= 1; ++dx) {
        const int r = row + dy;
        const int c = column + dx;
        if (r < 0 || r >= cells_ || c < 0 || c >= cells_) continue;
        const auto i = static_cast<std::size_t>(r * cells_ + c);
        if (region_[i] != 0 || cell(c, r) != Cell::kMatch) continue;
        region_[i] = 1;
        stack_[top++] = static_cast<int>(i);
      }
    }
  }
  // Cell (c, r) covers offsets [c cell - half, (c + 1) cell - half) from the fixation.
  const auto offset = [&](double cell_index) {
    return static_cast<float>((cell_index + 0.5) * cell_px_ - half);
  };
  out.cells = count;
  out.valid = count >= config_.min_cells;
  out.clipped =
      min_column == 0 || min_row == 0 || max_column == cells_ - 1 || max_row == cells_ - 1;
  out.centroid_x_px = offset(sum_x / count);
  out.centroid_y_px = offset(sum_y / count);
  out.left_px = offset(min_column) - 0.5f * static_cast<float>(cell_px_);
  out.right_px = offset(max_column) + 0.5f * static_cast<float>(cell_px_);
  out.top_px = offset(min_row) - 0.5f * static_cast<float>(cell_px_);
  out.bottom_px = offset(max_row) + 0.5f * static_cast<float>(cell_px_);
}

}  // namespace cambio::perception
