#include "cambio/perception/motion_estimator.hpp"

#include <algorithm>
#include <cmath>

#include "cambio/perception/gaussian_kernels.hpp"

namespace cambio::perception {

namespace {

// Bilinear sample at cell p (top-left) with fractions fx, fy.
inline float bilinear(const float* p, int width, float fx, float fy) {
  return (1.0f - fy) * ((1.0f - fx) * p[0] + fx * p[1]) +
         fy * ((1.0f - fx) * p[width] + fx * p[width + 1]);
}

// The cell and fraction of a sample coordinate, as floor and remainder.
inline void split_coordinate(float v, int& cell, float& frac) {
  cell = static_cast<int>(std::floor(v));
  frac = v - static_cast<float>(cell);
}

}  // namespace

MotionEstimator::MotionEstimator(const MotionConfig& config, double half_width_sigmas, int levels,
                                 int width, int height)
    : config_(config),
      levels_(levels),
      width_(width),
      height_(height),
      half_width_(gaussian_half_width(config.sigma_px, half_width_sigmas)) {
  const double sigma = config.sigma_px;
  smooth_taps_ = Taps::from(gaussian_derivative_kernel(0, Axis::kX, sigma, half_width_).row);
  // Eq. 4's factor along d with Eq. 3's normalised factor across d (= lambda g^(1)): the
  // derivative of the normalised 2-D Gaussian, so gradients are grey levels per level pixel.
  derivative_taps_ = Taps::from(gaussian_derivative_kernel(1, Axis::kX, sigma, half_width_).row);
  const std::size_t plane = static_cast<std::size_t>(width) * static_cast<std::size_t>(height);
  for (auto& frame : frames_) {
    frame.smooth.assign(plane * static_cast<std::size_t>(levels), 0.0f);
    frame.grad_x.assign(plane * static_cast<std::size_t>(levels), 0.0f);
    frame.grad_y.assign(plane * static_cast<std::size_t>(levels), 0.0f);
  }
  const std::size_t rows =
      static_cast<std::size_t>(width) * static_cast<std::size_t>(height + 2 * half_width_);
  rows_smooth_.assign(rows, 0.0f);
  rows_derivative_.assign(rows, 0.0f);
  cell_x_.assign(static_cast<std::size_t>(width), 0);
  frac_x_.assign(static_cast<std::size_t>(width), 0.0f);
  cell_y_.assign(static_cast<std::size_t>(height), 0);
  frac_y_.assign(static_cast<std::size_t>(height), 0.0f);
}

void MotionEstimator::filter(const Retina& retina, Frame& frame) noexcept {
  const std::size_t plane = static_cast<std::size_t>(width_) * static_cast<std::size_t>(height_);
  const int s = half_width_;
  frame.fixation = retina.fixation();
  for (int k = 0; k < levels_; ++k) {
    const RetinaLevelView level = retina.level(k);
    frame.scale[static_cast<std::size_t>(k)] = level.scale_px;
    const float* top = level.interior - s * level.stride;
    convolve_rows(top, level.stride, rows_smooth_.data(), width_, width_, height_ + 2 * s,
                  smooth_taps_);
    convolve_rows(top, level.stride, rows_derivative_.data(), width_, width_, height_ + 2 * s,
                  derivative_taps_);
    const std::ptrdiff_t centre = static_cast<std::ptrdiff_t>(s) * width_;
    const std::size_t offset = plane * static_cast<std::size_t>(k);
    convolve_columns(rows_smooth_.data() + centre, width_, frame.smooth.data() + offset, width_,
                     width_, height_, smooth_taps_);
    convolve_columns(rows_derivative_.data() + centre, width_, frame.grad_x.data() + offset, width_,
                     width_, height_, smooth_taps_);
    convolve_columns(rows_smooth_.data() + centre, width_, frame.grad_y.data() + offset, width_,
                     width_, height_, derivative_taps_);
  }
}

bool MotionEstimator::track_level(const Frame& now, const Frame& before, int k, float& ux,
                                  float& uy, LevelMotion& result) const noexcept {
  const std::size_t offset = static_cast<std::size_t>(width_) * static_cast<std::size_t>(height_) *
                             static_cast<std::size_t>(k);
  const float* s_now = now.smooth.data() + offset;
  const float* gx_now = now.grad_x.data() + offset;
  const float* gy_now = now.grad_y.data() + offset;
  const float* s_before = before.smooth.data() + offset;
  const float* gx_before = before.grad_x.data() + offset;
  const float* gy_before = before.grad_y.data() + offset;
  for (int iteration = 0; iteration < config_.iterations; ++iteration) {
    // S_now(p) = S_before(p - u): sample the previous frame at p - u, inside the map.
    const int margin = static_cast<int>(std::ceil(std::max(std::abs(ux), std::abs(uy)))) + 1;
    if (2 * margin + 2 > std::min(width_, height_)) return false;
    double a11 = 0.0, a12 = 0.0, a22 = 0.0, b1 = 0.0, b2 = 0.0, rr = 0.0;
    int n = 0;
    // The sample point (x - ux, y - uy) splits into a column part and a row part: one floor
    // per column and per row instead of three per pixel.
    for (int x = margin; x < width_ - margin; ++x) {
      const auto i = static_cast<std::size_t>(x);
      split_coordinate(static_cast<float>(x) - ux, cell_x_[i], frac_x_[i]);
    }
    for (int y = margin; y < height_ - margin; ++y) {
      const auto i = static_cast<std::size_t>(y);
      split_coordinate(static_cast<float>(y) - uy, cell_y_[i], frac_y_[i]);
    }
    for (int y = margin; y < height_ - margin; ++y) {
      const int row = cell_y_[static_cast<std::size_t>(y)] * width_;
      const float fy = frac_y_[static_cast<std::size_t>(y)];
      for (int x = margin; x < width_ - margin; ++x) {
        const std::ptrdiff_t cell = row + cell_x_[static_cast<std::size_t>(x)];
        const float fx = frac_x_[static_cast<std::size_t>(x)];
        const float previous = bilinear(s_before + cell, width_, fx, fy);
        const float gx =
            0.5f * (gx_now[y * width_ + x] + bilinear(gx_before + cell, width_, fx, fy));
        const float gy =
            0.5f * (gy_now[y * width_ + x] + bilinear(gy_before + cell, width_, fx, fy));
        const float it = s_now[y * width_ + x] - previous;
        a11 += gx * gx;
        a12 += gx * gy;
        a22 += gy * gy;
        b1 += gx * it;
        b2 += gy * it;
        rr += it * it;
        ++n;
      }
    }
    const double trace = a11 + a22;
    const double det = a11 * a22 - a12 * a12;
    const double min_eigen = 0.5 * (trace - std::sqrt(std::max(0.0, trace * trace - 4.0 * det)));
    result.min_eigenvalue = static_cast<float>(min_eigen / n);
    result.residual_rms = static_cast<float>(std::sqrt(rr / n));
    result.iterations = iteration + 1;
    if (result.min_eigenvalue < config_.min_eigenvalue || det <= 0.0) return false;
    // S_now - S_before(p - u - du) ~ it + grad . du = 0.
    const double dx = -(a22 * b1 - a12 * b2) / det;
    const double dy = -(a11 * b2 - a12 * b1) / det;
    ux += static_cast<float>(dx);
    uy += static_cast<float>(dy);
    if (std::abs(dx) < 1e-3 && std::abs(dy) < 1e-3) break;
  }
  const float limit = 0.5f * static_cast<float>(std::min(width_, height_)) - 1.0f;
  return std::abs(ux) < limit && std::abs(uy) < limit;
}

void MotionEstimator::estimate(const Retina& retina, MotionResult& out, float* temporal) noexcept {
  out = MotionResult{};
  const int next = 1 - current_;
  Frame& now = frames_[static_cast<std::size_t>(next)];
  const Frame& before = frames_[static_cast<std::size_t>(current_)];
  filter(retina, now);
  current_ = next;
  const bool had_previous = have_previous_;
  have_previous_ = true;
  if (!had_previous) {
    if (temporal != nullptr) std::fill(temporal, temporal + now.smooth.size(), 0.0f);
    return;
  }
  out.fixation_changed = now.fixation.x != before.fixation.x || now.fixation.y != before.fixation.y;
  if (temporal != nullptr) {
    for (std::size_t i = 0; i < now.smooth.size(); ++i)
      temporal[i] = now.smooth[i] - before.smooth[i];
  }
  if (out.fixation_changed) return;
  bool have_estimate = false;
  float estimate_x = 0.0f;
  float estimate_y = 0.0f;
  for (int k = levels_ - 1; k >= 0; --k) {
    const int scale = now.scale[static_cast<std::size_t>(k)];
    if (before.scale[static_cast<std::size_t>(k)] != scale) continue;
    float ux = have_estimate ? estimate_x / static_cast<float>(scale) : 0.0f;
    float uy = have_estimate ? estimate_y / static_cast<float>(scale) : 0.0f;
    LevelMotion& level = out.per_level[static_cast<std::size_t>(k)];
    level.valid = track_level(now, before, k, ux, uy, level);
    if (!level.valid) continue;
    level.flow_x_px = ux * static_cast<float>(scale);
    level.flow_y_px = uy * static_cast<float>(scale);
    have_estimate = true;
    estimate_x = level.flow_x_px;
    estimate_y = level.flow_y_px;
    out.valid = true;
    out.flow_x_px = estimate_x;
    out.flow_y_px = estimate_y;
    out.level = k;
  }
}

}  // namespace cambio::perception
