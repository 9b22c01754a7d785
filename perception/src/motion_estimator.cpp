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
  for (Frame* frame : {&frames_[0], &frames_[1], &key_}) {
    frame->smooth.assign(plane * static_cast<std::size_t>(levels), 0.0f);
    frame->grad_x.assign(plane * static_cast<std::size_t>(levels), 0.0f);
    frame->grad_y.assign(plane * static_cast<std::size_t>(levels), 0.0f);
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
    const double root = std::sqrt(std::max(0.0, trace * trace - 4.0 * det));
    const double min_eigen = 0.5 * (trace - root);
    const double max_eigen = 0.5 * (trace + root);
    result.min_eigenvalue = static_cast<float>(min_eigen / n);
    result.max_eigenvalue = static_cast<float>(max_eigen / n);
    result.gradient_orientation_rad = static_cast<float>(0.5 * std::atan2(2.0 * a12, a11 - a22));
    result.residual_rms = static_cast<float>(std::sqrt(rr / n));
    result.iterations = iteration + 1;
    if (max_eigen / n < config_.min_eigenvalue) return false;
    // S_now - S_before(p - u - du) ~ it + grad . du = 0, solved with a prior that the update is
    // zero (Tikhonov): along a direction the window has no structure in (stripes: the aperture
    // problem) the estimate keeps its initial value instead of following noise, while the
    // constrained direction converges to the same fixed point as without the prior.
    const double prior = kAperturePrior * max_eigen;
    const double r11 = a11 + prior;
    const double r22 = a22 + prior;
    const double rdet = r11 * r22 - a12 * a12;
    if (!(rdet > 0.0)) return false;
    const double dx = -(r22 * b1 - a12 * b2) / rdet;
    const double dy = -(r11 * b2 - a12 * b1) / rdet;
    ux += static_cast<float>(dx);
    uy += static_cast<float>(dy);
    if (std::abs(dx) < 1e-3 && std::abs(dy) < 1e-3) break;
  }
  const float limit = 0.5f * static_cast<float>(std::min(width_, height_)) - 1.0f;
  return std::abs(ux) < limit && std::abs(uy) < limit;
}

void MotionEstimator::estimate(const Retina& retina, MotionResult& out, float* temporal) noexcept {
  out = MotionResult{};
  out.frame = ++frames_seen_;
  const int next = 1 - current_;
  Frame& now = frames_[static_cast<std::size_t>(next)];
  const Frame& before = frames_[static_cast<std::size_t>(current_)];
  filter(retina, now);
  current_ = next;
  const bool had_previous = have_previous_;
  have_previous_ = true;
  if (!had_previous) {
    if (temporal != nullptr) std::fill(temporal, temporal + now.smooth.size(), 0.0f);
    have_key_ = false;
    have_fovea_flow_ = false;
    track_key(now, out, out);
    return;
  }
  out.fixation_changed = now.fixation.x != before.fixation.x || now.fixation.y != before.fixation.y;
  if (temporal != nullptr) {
    for (std::size_t i = 0; i < now.smooth.size(); ++i)
      temporal[i] = now.smooth[i] - before.smooth[i];
  }
  if (!out.fixation_changed) {
    out.valid = track(now, before, levels_ - 1, 0.0f, 0.0f, out.flow_x_px, out.flow_y_px, out.level,
                      &out.per_level);
    retry_fine_levels_from_last_flow(now, before, out);
  }
  classify_structure(out);
  have_fovea_flow_ = !out.fixation_changed && out.valid && out.level <= 1;
  if (have_fovea_flow_) {
    fovea_flow_x_ = out.flow_x_px;
    fovea_flow_y_ = out.flow_y_px;
  }
  track_key(now, out, out);
}

void MotionEstimator::classify_structure(MotionResult& out) const noexcept {
  if (!out.valid || out.level < 0 || out.level >= levels_ - 1) return;
  for (int k = 0; k < levels_ - 1; ++k) {
    const LevelMotion& level = out.per_level[static_cast<std::size_t>(k)];
    if (level.valid && level.min_eigenvalue >= kOneDirectionalRatio * level.max_eigenvalue) return;
  }
  out.one_directional = true;
  out.gradient_orientation_rad =
      out.per_level[static_cast<std::size_t>(out.level)].gradient_orientation_rad;
}

void MotionEstimator::retry_fine_levels_from_last_flow(const Frame& now, const Frame& before,
                                                       MotionResult& out) noexcept {
  if ((out.valid && out.level == 0) || !have_fovea_flow_) return;
  float flow_x = 0.0f;
  float flow_y = 0.0f;
  int level = -1;
  std::array<LevelMotion, Retina::kMaxLevels> levels = out.per_level;
  if (!track(now, before, std::min(1, levels_ - 1), fovea_flow_x_, fovea_flow_y_, flow_x, flow_y,
             level, &levels) ||
      (out.valid && level >= out.level)) {
    return;
  }
  out.valid = true;
  out.flow_x_px = flow_x;
  out.flow_y_px = flow_y;
  out.level = level;
  out.per_level = levels;
}

void MotionEstimator::track_key(const Frame& now, const MotionResult& frame_to_frame,
                                MotionResult& out) noexcept {
  bool renew = !have_key_ || now.fixation.x != key_.fixation.x ||
               now.fixation.y != key_.fixation.y || !frame_to_frame.valid;
  if (!renew) {
    // From where the key's content was in the previous frame, moved by this frame's flow.
    // That guess is good to the frame's error: only the finest levels refine it (a coarse
    // level's window is dominated by the surround, whose motion differs from the fovea's).
    const float initial_x = key_to_previous_x_ + frame_to_frame.flow_x_px;
    const float initial_y = key_to_previous_y_ + frame_to_frame.flow_y_px;
    int level = -1;
    out.key_valid = track(now, key_, std::min(1, levels_ - 1), initial_x, initial_y,
                          out.key_flow_x_px, out.key_flow_y_px, level, nullptr) &&
                    std::hypot(out.key_flow_x_px - initial_x, out.key_flow_y_px - initial_y) <=
                        kMaxKeyCorrectionPx;
    out.key_frame = key_frame_;
    ++key_age_frames_;
    renew = !out.key_valid || key_age_frames_ >= config_.rekey_frames ||
            std::hypot(out.key_flow_x_px, out.key_flow_y_px) > config_.rekey_shift_px;
    key_to_previous_x_ = out.key_flow_x_px;
    key_to_previous_y_ = out.key_flow_y_px;
  }
  if (renew) {
    // Same sizes: the copies reuse key_'s storage.
    key_.smooth = now.smooth;
    key_.grad_x = now.grad_x;
    key_.grad_y = now.grad_y;
    key_.scale = now.scale;
    key_.fixation = now.fixation;
    have_key_ = true;
    key_frame_ = out.frame;
    key_age_frames_ = 0;
    key_to_previous_x_ = 0.0f;
    key_to_previous_y_ = 0.0f;
  }
}

bool MotionEstimator::track(const Frame& now, const Frame& reference, int from_level,
                            float initial_x, float initial_y, float& flow_x, float& flow_y,
                            int& finest_level,
                            std::array<LevelMotion, Retina::kMaxLevels>* levels) const noexcept {
  bool valid = false;
  float estimate_x = initial_x;
  float estimate_y = initial_y;
  for (int k = from_level; k >= 0; --k) {
    const int scale = now.scale[static_cast<std::size_t>(k)];
    if (reference.scale[static_cast<std::size_t>(k)] != scale) continue;
    float ux = estimate_x / static_cast<float>(scale);
    float uy = estimate_y / static_cast<float>(scale);
    LevelMotion scratch;
    LevelMotion& level = levels != nullptr ? (*levels)[static_cast<std::size_t>(k)] : scratch;
    level.valid = track_level(now, reference, k, ux, uy, level);
    if (!level.valid) continue;
    level.flow_x_px = ux * static_cast<float>(scale);
    level.flow_y_px = uy * static_cast<float>(scale);
    estimate_x = level.flow_x_px;
    estimate_y = level.flow_y_px;
    valid = true;
    flow_x = estimate_x;
    flow_y = estimate_y;
    finest_level = k;
  }
  return valid;
}

}  // namespace cambio::perception
