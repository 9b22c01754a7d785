#pragma once

#include <algorithm>
#include <array>
#include <memory>
#include <vector>

#include "cambio/hal/image.hpp"
#include "cambio/perception/feature_maps.hpp"
#include "cambio/perception/operator_bank.hpp"
#include "cambio/perception/perception_config.hpp"
#include "cambio/perception/retina.hpp"

namespace cambio::perception {

/// One disparity the fixated patch may have: a local maximum of the scan's correlation.
struct DisparityCandidate {
  float disparity_px = 0.0f;  ///< x_left - x_right, level-0 px (sub-block: parabola peak).
  float score = 0.0f;         ///< ZNCC at the scan level.
  /// ZNCC of the next wider window (the fixated object with its outline and surround) at this
  /// disparity: what tells apart the alike peaks of a periodic texture.
  float context_score = 0.0f;
};

/// What a scan found, best candidate first.
struct DisparityScanResult {
  static constexpr int kMaxCandidates = 4;
  bool searched = false;
  int level = -1;    ///< The retina level scanned.
  int scale_px = 0;  ///< Its block size.
  int shifts = 0;    ///< Shifts scored (inside the image).
  float texture_rms = 0.0f;
  /// The window that decided: 0 the scan's own, 1 twice and 2 four times as wide (the smaller
  /// ones scored several shifts alike, or saw too little structure along x).
  int window_tier = 0;
  int window_samples = 0;  ///< The deciding window's samples (width x height).
  /// The deciding window's best peak falls away on both sides (kLocalizedDrop within
  /// kLocalizedFlank samples): false when even the widest window scored a plateau (texture along
  /// x only), whose best shift says nothing of the depth.
  bool localized = false;
  int count = 0;
  std::array<DisparityCandidate, kMaxCandidates> candidates{};
};

/// The whole disparity range a rig can produce, searched at once for the fixated patch.
///
/// Why: a coarse-to-fine search starting from a field-covering level matches whatever fills
/// that level's window (a backdrop, another object) and cannot recover when that is not the
/// fixated surface; and a finer level can only search what its small retina overlaps. The scan
/// takes the finest retina level whose correlation window spans at least scan_window_px (about
/// the fovea's size: the fixated surface dominates it), builds the right eye's samples of that
/// level over a strip wide enough for every disparity up to scan_range_px, computes the
/// disparity features on it with the same operators, and scores the left window against every
/// shift. Its local maxima are candidates; the estimator refines each at the finer levels and
/// keeps the one the fixated patch agrees with (several hypotheses, as population codes of
/// disparity-tuned units keep several, instead of one coarse guess).
///
/// A periodic texture (a checkerboard) gives several alike peaks, and a texture without
/// structure along x (horizontal stripes: the aperture problem) scores every shift alike. The
/// window then grows (adaptive windows, as in Kanade and Okutomi's stereo): when the best peak
/// does not beat every other by kDecisiveMargin, or is the top of a plateau rather than a peak
/// (texture almost along x: its top is set by the stripes' tilt and any vertical disparity, not
/// by the depth), or the next wider window scores another peak
/// higher by that margin, the whole range is scored again with a window
/// twice as wide, then four times: its view of the object's outline and surround matches at the
/// true disparity only. The decisive window's local maxima are the candidates, each with the next
/// wider window's score as its context. The window grows only where the smaller one cannot decide,
/// because a wide window mixes the fixated object with whatever surrounds it at other disparities.
///
/// Cost: one strip level (width + 2 scan_range / scale samples) and its features, a left level
/// as wide as the widest window, then one ZNCC per shift (and per shift again for each wider
/// window the scene needs). Allocates in the constructor only;
/// scan() is real-time safe.
class DisparityScan {
 public:
  /// `bank` is the SSM's operator bank (the maps are looked up by the disparity features' names);
  /// the retina's size and levels are the SSM's. Throws std::invalid_argument on a config the
  /// estimator would refuse. With config.scan_range_px <= 0 the scan is off (enabled() false).
  DisparityScan(const DisparityConfig& disparity, const OperatorConfig& operators,
                const OperatorBank& bank, const RetinaConfig& retina, int image_width_px,
                int image_height_px);
  ~DisparityScan();

  /// Windows tried, from the scan's own (tier 0) to four times as wide.
  static constexpr int kWindowTiers = 3;
  /// How far the best peak must lead every other (ZNCC) for a window to decide.
  static constexpr float kDecisiveMargin = 0.1f;
  /// The least share of x structure (window_x_structure) with which a refinement level's
  /// window is matched (the estimator's aperture test).
  static constexpr float kMinXStructure = 0.1f;
  /// A peak is localized when, on each side, a shift at most kLocalizedFlank samples away scores
  /// kLocalizedDrop less (a rounded peak of coarse texture falls by 0.04 three samples away, a
  /// fine texture by 0.2 one sample away; a plateau by 0.005).
  static constexpr int kLocalizedFlank = 3;
  static constexpr float kLocalizedDrop = 0.02f;

  bool enabled() const { return enabled_; }
  /// The eyes' lenses for the strip (right) and the left context (SensoryServo::set_lenses).
  void set_lenses(std::shared_ptr<const LensCornerMap> left,
                  std::shared_ptr<const LensCornerMap> right);
  int level() const { return level_; }

  /// Scores the left retina's window at level() (`left`, the SSM's left feature maps) against
  /// the right image around `right_fixation`. Real-time safe; not thread-safe.
  void scan(const FeatureMaps& left, const hal::Image& left_image, PixelPoint left_fixation,
            const hal::Image& right, PixelPoint right_fixation, DisparityScanResult& out) noexcept;

 private:
  /// ZNCC at `shift` of window `tier` (half-width half_ << tier): the left window from the
  /// SSM's level for tier 0, from the wider left context level above it.
  float score(int tier, const float* left_level, int shift) const noexcept;
  struct ProfileVerdict {
    bool decisive = false;   ///< The best peak leads every other local maximum by kDecisiveMargin.
    bool localized = false;  ///< And stands out from its flanks (kLocalizedDrop).
  };
  /// Scores every shift with window `tier` into scores_ (kOutside past the image) and judges
  /// its best peak.
  ProfileVerdict score_profile(int tier, const float* left_level,
                               const RetinaLevelView& strip) noexcept;
  /// The local maxima of scores_ (window `tier`), best first, into `out`.
  void collect_candidates(int tier, const float* left_level, const RetinaLevelView& strip,
                          DisparityScanResult& out) const noexcept;
  int tier_half(int tier) const { return half_ << tier; }
  int tier_half_y(int tier) const { return std::min(half_ << tier, (height_ - 1) / 2); }
  /// Whether the right window of half-width `half` at `shift` lies inside the image.
  bool inside(const RetinaLevelView& strip, int shift, int half) const noexcept;

  bool enabled_ = false;
  int level_ = 0;
  int width_ = 0;  ///< The SSM retina's width (samples).
  int height_ = 0;
  int half_ = 0;  ///< Correlation window half-width, samples.
  int half_y_ = 0;
  int range_ = 0;  ///< Shifts searched each way, samples.
  int strip_width_ = 0;
  int image_width_ = 0;
  std::vector<int> features_;
  MapMask required_ = 0;
  int context_width_ = 0;  ///< The left context level's width: the widest window's.
  std::unique_ptr<Retina> strip_;
  std::unique_ptr<OperatorBank> strip_bank_;
  std::vector<float> strip_maps_;  ///< features x strip_width x height.
  std::unique_ptr<Retina> left_context_;
  std::unique_ptr<OperatorBank> context_bank_;
  std::vector<float> context_maps_;  ///< features x context_width x height.
  std::vector<float> scores_;        ///< Indexed by shift + range_.
};

}  // namespace cambio::perception
