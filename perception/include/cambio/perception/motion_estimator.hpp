#pragma once

#include <array>
#include <cstdint>
#include <vector>

#include "cambio/perception/convolution.hpp"
#include "cambio/perception/perception_config.hpp"
#include "cambio/perception/retina.hpp"

namespace cambio::perception {

struct LevelMotion {
  bool valid = false;
  float flow_x_px = 0.0f;  ///< Image motion between the two frames, level-0 px per frame.
  float flow_y_px = 0.0f;
  float min_eigenvalue = 0.0f;  ///< Of the per-pixel structure tensor (grey^2 / level px^2).
  float residual_rms = 0.0f;    ///< Grey levels after the last warp.
  int iterations = 0;
  float max_eigenvalue = 0.0f;
  /// The direction of the strongest gradient (the larger eigenvalue's), from +x towards +y, in
  /// (-pi/2, pi/2]. With min_eigenvalue far below max_eigenvalue (stripes, one edge: the
  /// aperture problem) only the flow along it is measured; across it the estimate is the prior.
  float gradient_orientation_rad = 0.0f;
};

/// Motion of one eye between its previous and current retina (paper Section 3: "motion features
/// are also computed from two consecutive MR image frames").
struct MotionResult {
  bool valid = false;
  bool fixation_changed = false;  ///< The retina moved in the image: no temporal derivative.
  float flow_x_px = 0.0f;         ///< From the finest valid level, level-0 px per frame.
  float flow_y_px = 0.0f;
  int level = -1;
  std::array<LevelMotion, Retina::kMaxLevels> per_level{};
  /// The displacement of the content since the key frame (a frame held for several frames):
  /// S_now(p) = S_key(p - key_flow). Summing per-frame flows sums their errors; a tracker that
  /// places its target by key_flow drifts only by one estimate's error per key.
  bool key_valid = false;
  float key_flow_x_px = 0.0f;
  float key_flow_y_px = 0.0f;
  /// Every level below the coarsest that gave an estimate saw structure in one direction only
  /// (stripes, or one edge, filling the window: the aperture problem): the flow is measured
  /// along `gradient_orientation_rad` (the finest level's strongest gradient, from +x towards
  /// +y) and, across it, is the coarsest level's, whose window is mostly the surround.
  bool one_directional = false;
  float gradient_orientation_rad = 0.0f;
  std::uint64_t frame = 0;      ///< This frame's number (frames the estimator has consumed).
  std::uint64_t key_frame = 0;  ///< The number of the frame key_flow is measured from.
};

/// Per level: the temporal derivative of the Gaussian-smoothed level (current minus previous)
/// and a translation by iterative Lucas-Kanade, coarse to fine. Smoothing and gradients use the
/// paper's kernels: S = g_x^(0) g_y^(0) * I (Eq. 3 both ways, a normalised 2-D Gaussian) and
/// grad S = lambda (G_x^(1), G_y^(1)) (Eq. 4; lambda restores the normalisation of the factor
/// across d). Keeps the previous frame's maps; not thread-safe.
class MotionEstimator {
 public:
  MotionEstimator(const MotionConfig& config, double half_width_sigmas, int levels, int width,
                  int height);

  int apron_px() const { return half_width_; }
  /// Forgets the previous frame (the next estimate is invalid).
  void reset() noexcept { have_previous_ = false; }

  /// Consumes the current retina. `temporal` (levels x width x height floats, or null) receives
  /// S_now - S_previous per level. Real-time safe.
  void estimate(const Retina& retina, MotionResult& out, float* temporal) noexcept;

  /// The most the key may correct the sum of the frames' flows since it (level-0 px). That sum
  /// errs by a fraction of a pixel (a few frames' noise); a larger correction is the key's
  /// content matched one period off on a periodic texture (checkers: 3-8 px jumps), and would
  /// move a pursued target's position by that much. Such a key is not valid and is renewed.
  static constexpr double kMaxKeyCorrectionPx = 2.0;
  /// A level whose structure tensor's smaller eigenvalue is below this fraction of the larger
  /// sees one direction only (stripes score below 0.005; a textured fovea rarely below 0.03).
  static constexpr double kOneDirectionalRatio = 0.01;

 private:
  struct Frame {
    std::vector<float> smooth;  ///< Per level, width x height.
    std::vector<float> grad_x;
    std::vector<float> grad_y;
    std::array<int, Retina::kMaxLevels> scale{};
    PixelPoint fixation;
  };
  void filter(const Retina& retina, Frame& frame) noexcept;
  /// Coarse to fine from `from_level` and `initial` (level-0 px): `now` against `reference`;
  /// fills `levels`
  /// (may be null) and returns whether a level gave an estimate, in flow_x/flow_y.
  bool track(const Frame& now, const Frame& reference, int from_level, float initial_x,
             float initial_y, float& flow_x, float& flow_y, int& finest_level,
             std::array<LevelMotion, Retina::kMaxLevels>* levels) const noexcept;
  /// When coarse to fine did not reach the fovea (level 0), its two finest levels again, started
  /// from the previous frame's flow if that was measured there. The coarse levels' windows are
  /// mostly the surround: where its motion is not the fovea's (a target pursued across a
  /// background, worse a periodic one) the fine levels, started from it, diverge; a fixated
  /// target's own motion changes little from one frame to the next. Replaces `out`'s estimate
  /// only when the retry reaches a finer level.
  void retry_fine_levels_from_last_flow(const Frame& now, const Frame& before,
                                        MotionResult& out) noexcept;
  /// Sets out.one_directional and its orientation from the levels' structure.
  void classify_structure(MotionResult& out) const noexcept;
  /// The displacement since the key frame, then whether `now` becomes the next key.
  void track_key(const Frame& now, const MotionResult& frame_to_frame, MotionResult& out) noexcept;
  bool track_level(const Frame& now, const Frame& before, int k, float& ux, float& uy,
                   LevelMotion& result) const noexcept;

  /// The prior's weight against the structure tensor's larger eigenvalue: a direction with less
  /// than about this fraction of the other's structure is treated as unobserved.
  static constexpr double kAperturePrior = 0.05;
  MotionConfig config_;
  int levels_ = 0;
  int width_ = 0;
  int height_ = 0;
  int half_width_ = 0;
  Taps smooth_taps_;
  Taps derivative_taps_;
  std::array<Frame, 2> frames_;
  int current_ = 0;
  bool have_previous_ = false;
  Frame key_;
  bool have_key_ = false;
  std::uint64_t frames_seen_ = 0;
  std::uint64_t key_frame_ = 0;
  int key_age_frames_ = 0;
  /// The previous frame's flow, when it was measured at the two finest levels.
  bool have_fovea_flow_ = false;
  float fovea_flow_x_ = 0.0f;
  float fovea_flow_y_ = 0.0f;
  float key_to_previous_x_ = 0.0f;  ///< key_flow of the previous frame.
  float key_to_previous_y_ = 0.0f;
  std::vector<float> rows_smooth_;  ///< Row-pass scratch, width x (height + 2 half_width).
  std::vector<float> rows_derivative_;
  /// Per iteration of track_level: the bilinear cell and weight of every column (x - ux) and
  /// row (y - uy), computed once instead of per pixel and per plane.
  mutable std::vector<int> cell_x_;
  mutable std::vector<int> cell_y_;
  mutable std::vector<float> frac_x_;
  mutable std::vector<float> frac_y_;
};

}  // namespace cambio::perception
