#pragma once

#include <array>
#include <vector>

#include "cambio/perception/disparity_scan.hpp"
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
  /// The window's features barely vary along x (horizontal stripes: the aperture problem), so
  /// every shift scores alike: the level is not matched and keeps the coarser estimate.
  bool aperture = false;
  float x_structure = 0.0f;   ///< window_x_structure of the left window (0.5: isotropic).
  float disparity_px = 0.0f;  ///< x_left - x_right, level-0 px.
  float confidence = 0.0f;    ///< In [0, 1]: peak correlation x distinctiveness x texture.
  float peak_score = 0.0f;    ///< Zero-mean normalised cross-correlation at the best shift.
  float texture_rms = 0.0f;   ///< Rms deviation of the left window's features.
  int scale_px = 1;
  int search_min_px = 0;  ///< Searched shifts, level px (window offset included).
  int search_max_px = 0;
  /// Right windows moved (ShiftedLevelSource) to score shifts beyond the overlap of the two
  /// retinas as built; 0 when the search fitted.
  int moved_windows = 0;
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
  int candidates = 0;  ///< Hypotheses of the whole-range scan compared (0: no scan).
  /// The scan's last window (DisparityScanResult::window_tier): the one that decided, or the
  /// widest (DisparityScan::kWindowTiers - 1) when none did; 0 is the fovea's; -1 without a scan.
  int scan_window_tier = -1;
  std::array<LevelDisparity, Retina::kMaxLevels> per_level{};
};

/// Right-eye levels with a moved window, for finer levels whose coarser estimate lies beyond
/// the overlap of the two retinas as built (the SSM implements it from the right image).
class ShiftedLevelSource {
 public:
  virtual ~ShiftedLevelSource() = default;
  /// Right level k rebuilt with its fixation moved `offset_px` level px to the left (sample x
  /// then holds what sample x - offset_px would), with at least the estimator's required maps
  /// computed, laid out as FeatureMaps::level(k). nullptr if it cannot be built. Real-time safe.
  virtual const float* shifted_right_level(int k, int offset_px) noexcept = 0;
};

/// Coarse-to-fine correlation of second-order Gaussian-derivative maps (paper Section 3: "a
/// simple correlation approach is used over the above second order Gaussian derivative,
/// considering estimations given by previous levels"). The coarsest level searches the
/// configured range; each finer level searches +- refine_range_px around the coarser estimate
/// scaled up (wider after a field-covering level many octaves coarser, and one scan block wider
/// below the whole-range scan, keeping the peak nearest its estimate unless another is
/// DisparityScan::kDecisiveMargin better). Shifts beyond the
/// overlap of the two retinas (a 16-px fovea with a 9-px window holds -3 .. +4 px) are scored
/// against right windows moved through a ShiftedLevelSource, so every level refines whatever
/// disparity the coarser level found. The score is the zero-mean normalised cross-correlation of a
/// (2h+1)^2 window at the centre, summed over the configured maps; a parabola through the best
/// score and its two neighbours gives the sub-pixel shift. Untextured windows (rms feature
/// deviation below min_texture_rms) are invalid rather than guessed, and so are windows with too
/// little structure along x (window_x_structure below DisparityScan::kMinXStructure), whose best
/// shift would be noise: both keep the coarser level's estimate.
class DisparityEstimator {
 public:
  /// Throws std::invalid_argument when a feature name is not in `bank` or the window does not fit.
  DisparityEstimator(const DisparityConfig& config, const OperatorBank& bank, int width,
                     int height);

  /// The maps the estimator reads (add them to the request).
  MapMask required_maps() const { return required_; }
  int window_half_px() const { return half_; }

  /// Real-time safe; not thread-safe (scratch). Retinas give each level's block size.
  /// Without `shifted`, a level whose refinement range leaves the overlap stops the descent.
  /// With a `scan` (DisparityScan) its candidates are refined from the level below the scan's
  /// and the best kept; the confidence then is mean peak^2 x margin over the runner-up x texture.
  void estimate(const FeatureMaps& left, const FeatureMaps& right, const Retina& left_retina,
                const Retina& right_retina, DisparityResult& out,
                ShiftedLevelSource* shifted = nullptr,
                const DisparityScanResult* scan = nullptr) const noexcept;

 private:
  /// ZNCC of the left window against the right window shifted by `shift` level px; both
  /// arguments point at one level's planes (FeatureMaps::level layout).
  float score(const float* left, const float* right, int shift) const noexcept;
  float left_texture(const float* left) const noexcept;
  /// Coarse-to-fine from `from_level` down to level 0, from a coarser estimate if one is given
  /// (`from_scan`: the scan's, which the first level refines over one scan block more).
  void descend(const FeatureMaps& left, const FeatureMaps& right, const Retina& left_retina,
               const Retina& right_retina, int from_level, bool have_estimate, double estimate_px,
               int coarser_scale, DisparityResult& out, ShiftedLevelSource* shifted,
               bool from_scan = false) const noexcept;
  /// A scan candidate's case after its descent: its score summed over the levels compared, the
  /// weight they sum to, and the most textured of them. The defaults stand for no candidate.
  struct CandidateEvidence {
    float key = -1e9f;
    float weight = 1.0f;
    float texture = 0.0f;
    /// The scan's peak stood out, or a finer level matched (DisparityScanResult::localized).
    bool localized = false;
  };
  /// Refines each scan candidate (keys_, refined_) and puts the best's descent in `out`.
  CandidateEvidence refine_candidates(const FeatureMaps& left, const FeatureMaps& right,
                                      const Retina& left_retina, const Retina& right_retina,
                                      const DisparityScanResult& scan, DisparityResult& out,
                                      ShiftedLevelSource* shifted) const noexcept;
  /// One candidate's descent from the level below the scan's, into trial_.
  void descend_from_candidate(const FeatureMaps& left, const FeatureMaps& right,
                              const Retina& left_retina, const Retina& right_retina,
                              const DisparityScanResult& scan, const DisparityCandidate& candidate,
                              int levels, ShiftedLevelSource* shifted) const noexcept;
  CandidateEvidence weigh_candidate(const DisparityScanResult& scan,
                                    const DisparityCandidate& candidate,
                                    const DisparityResult& trial) const noexcept;
  /// The best key of a candidate that refined to another disparity than `winner_px`; -1e9 for
  /// none.
  float runner_up_key(const DisparityScanResult& scan, float winner_px) const noexcept;
  /// `window_samples`: the scan's deciding window's (DisparityScanResult::window_samples).
  float scan_confidence(const CandidateEvidence& best, float second_key,
                        int window_samples) const noexcept;
  /// The winner's lead over the runner-up (ZNCC per level) at which it is fully distinct, for
  /// the estimator's own window (a wider deciding window needs less).
  static constexpr double kDistinctMargin = 0.3;
  /// The share of the confidence a disparity keeps when no window localized it.
  static constexpr double kUnlocalizedShare = 0.1;
  /// How much a finer level's peak counts, against the scan level's, in choosing a candidate.
  static constexpr float kFinerLevelWeight = 0.5f;
  const float* plane(const float* level, int map) const {
    return level + static_cast<std::ptrdiff_t>(map) * width_ * height_;
  }

  DisparityConfig config_;
  std::vector<int> features_;
  MapMask required_ = 0;
  int width_ = 0;
  int height_ = 0;
  int half_ = 0;
  int half_y_ = 0;
  mutable std::vector<float> scores_;  ///< Indexed by shift - lowest shift searched.
  mutable DisparityResult trial_;      ///< One scan candidate's descent.
  mutable std::array<float, DisparityScanResult::kMaxCandidates> keys_{};
  mutable std::array<float, DisparityScanResult::kMaxCandidates> refined_{};
};

}  // namespace cambio::perception
