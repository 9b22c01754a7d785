#pragma once

#include <array>
#include <vector>

#include "cambio/perception/feature_maps.hpp"
#include "cambio/perception/operator_bank.hpp"
#include "cambio/perception/perception_config.hpp"
#include "cambio/perception/retina.hpp"

namespace cambio::perception {

/// The estimate of one retina level.
struct LevelDisparity {
  bool searched = false;       ///< False when the level could not hold the coarser estimate.
  bool valid = false;          ///< Textured enough and matched inside the search range.
  bool at_range_edge = false;  ///< Best match on the range's edge: not trusted (invalid).
  float disparity_px = 0.0f;   ///< x_left - x_right, level-0 px.
  float confidence = 0.0f;     ///< In [0, 1]: peak correlation x distinctiveness x texture.
  float peak_score = 0.0f;     ///< Zero-mean normalised cross-correlation at the best shift.
  float texture_rms = 0.0f;    ///< Rms deviation of the left window's features.
  int scale_px = 1;
  int search_min_px = 0;  ///< Searched shifts, level px.
  int search_max_px = 0;
};

/// Disparity of the retinas' centres. disparity_px = x_left - x_right of the same scene point in
/// level-0 (source) pixels, measured relative to each retina's fixation point: with both retinas
/// on their eyes' fixation points it is the vergence error; with equal fixations it is the
/// image disparity.
struct DisparityResult {
  bool valid = false;
  float disparity_px = 0.0f;
  float confidence = 0.0f;
  int level = -1;  ///< The finest level that produced the estimate.
  int levels = 0;
  std::array<LevelDisparity, Retina::kMaxLevels> per_level{};
};

/// Coarse-to-fine correlation of second-order Gaussian-derivative maps (paper Section 3: "a
/// simple correlation approach is used over the above second order Gaussian derivative,
/// considering estimations given by previous levels"). The coarsest level searches the
/// configured range; each finer level searches +- refine_range_px around the coarser estimate
/// scaled up. The score is the zero-mean normalised cross-correlation of a (2h+1)^2 window at
/// the centre, summed over the configured maps; a parabola through the best score and its two
/// neighbours gives the sub-pixel shift. Untextured windows (rms feature deviation below
/// min_texture_rms) are invalid rather than guessed.
class DisparityEstimator {
 public:
  /// Throws std::invalid_argument when a feature name is not in `bank` or the window does not fit.
  DisparityEstimator(const DisparityConfig& config, const OperatorBank& bank, int width,
                     int height);

  /// The maps the estimator reads (add them to the request).
  MapMask required_maps() const { return required_; }
  int window_half_px() const { return half_; }

  /// Real-time safe; not thread-safe (scratch). Retinas give each level's block size.
  void estimate(const FeatureMaps& left, const FeatureMaps& right, const Retina& left_retina,
                const Retina& right_retina, DisparityResult& out) const noexcept;

 private:
  /// ZNCC of the left window against the right window shifted by `shift` level px.
  float score(const FeatureMaps& left, const FeatureMaps& right, int level,
              int shift) const noexcept;
  float left_texture(const FeatureMaps& left, int level) const noexcept;

  DisparityConfig config_;
  std::vector<int> features_;
  MapMask required_ = 0;
  int width_ = 0;
  int height_ = 0;
  int half_ = 0;
  int half_y_ = 0;
  mutable std::vector<float> scores_;  ///< Indexed by shift + width.
};

}  // namespace cambio::perception
