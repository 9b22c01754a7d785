#include "cambio/perception/disparity_scan.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "cambio/perception/window_zncc.hpp"

namespace cambio::perception {

namespace {

/// A score for a shift whose right window leaves the image: beyond it the strip replicates the
/// edge, which can correlate with anything.
constexpr float kOutside = -2.0f;

/// The half-width (samples) of the mask that makes `spec`, as the operator bank builds it.
int mask_half_width(const MapSpec& spec, const OperatorConfig& operators, int bank_apron) {
  switch (spec.kind) {
    case MapKind::kIntensity:
      return 0;
    case MapKind::kGaussian:
    case MapKind::kLaplacian:
      return operators.half_width_px > 0
                 ? operators.half_width_px
                 : static_cast<int>(std::ceil(operators.half_width_sigmas * spec.sigma_px));
    default:
      return bank_apron;
  }
}

}  // namespace

DisparityScan::DisparityScan(const DisparityConfig& disparity, const OperatorConfig& operators,
                             const OperatorBank& bank, const RetinaConfig& retina,
                             int image_width_px, int image_height_px)
    : width_(retina.width_px), height_(retina.height_px), image_width_(image_width_px) {
  if (!disparity.enabled || !(disparity.scan_range_px > 0.0)) return;
  half_ = disparity.window_half_px > 0 ? disparity.window_half_px : std::max(1, width_ / 4);
  half_y_ = std::min(half_, (height_ - 1) / 2);
  // The finest level whose window spans scan_window_px; a field-covering coarsest level has
  // blocks of another size than the strip would, so it is not a candidate.
  const int last = retina.coarsest_covers_field ? retina.levels - 2 : retina.levels - 1;
  if (last < 0) return;
  level_ = last;
  for (int k = 0; k <= last; ++k) {
    if ((2 * half_ + 1) * (1 << k) >= disparity.scan_window_px) {
      level_ = k;
      break;
    }
  }
  const int scale = 1 << level_;
  range_ = static_cast<int>(std::ceil(disparity.scan_range_px / scale));
  context_width_ = 2 * tier_half(kWindowTiers - 1) + 2;
  strip_width_ = std::max(width_, context_width_) + 2 * range_;

  int apron = 0;
  const auto& specs = bank.maps();
  for (const auto& name : disparity.features) {
    const int index = bank.find(name);
    if (index < 0) throw std::invalid_argument("disparity feature '" + name + "' is not a map");
    features_.push_back(index);
    required_ |= MapMask{1} << index;
    apron = std::max(
        apron, mask_half_width(specs[static_cast<std::size_t>(index)], operators, bank.apron_px()));
  }
  RetinaConfig strip_config;
  strip_config.levels = level_ + 1;
  strip_config.width_px = strip_width_;
  strip_config.height_px = height_;
  strip_config.coarsest_covers_field = false;
  strip_ = std::make_unique<Retina>(strip_config, apron, image_width_px, image_height_px);
  strip_bank_ = std::make_unique<OperatorBank>(operators, strip_width_, height_);
  strip_maps_.assign(static_cast<std::size_t>(strip_bank_->map_count()) * strip_width_ * height_,
                     0.0f);
  RetinaConfig context_config = strip_config;
  context_config.width_px = context_width_;
  left_context_ = std::make_unique<Retina>(context_config, apron, image_width_px, image_height_px);
  context_bank_ = std::make_unique<OperatorBank>(operators, context_width_, height_);
  context_maps_.assign(
      static_cast<std::size_t>(context_bank_->map_count()) * context_width_ * height_, 0.0f);
  scores_.assign(static_cast<std::size_t>(2 * range_ + 1), 0.0f);
  enabled_ = true;
}

DisparityScan::~DisparityScan() = default;

void DisparityScan::set_lenses(std::shared_ptr<const LensCornerMap> left,
                               std::shared_ptr<const LensCornerMap> right) {
  if (!enabled_) return;
  strip_->set_lens(std::move(right));
  left_context_->set_lens(std::move(left));
}

float DisparityScan::score(int tier, const float* left_level, int shift) const noexcept {
  // The left window at its level's centre against the strip's window `shift` samples to the
  // left of the strip's centre (x_right = x_left - d).
  const bool fovea = tier == 0;
  return window_zncc(fovea ? left_level : context_maps_.data(), fovea ? width_ : context_width_,
                     (fovea ? width_ : context_width_) / 2, strip_maps_.data(), strip_width_,
                     strip_width_ / 2 - shift, height_ / 2, height_, tier_half(tier),
                     tier_half_y(tier), features_);
}

bool DisparityScan::inside(const RetinaLevelView& strip, int shift, int half) const noexcept {
  const int first = strip_width_ / 2 - shift - half;
  const double left_px = strip.origin_x_px + static_cast<double>(first) * strip.scale_px;
  const double right_px = left_px + static_cast<double>(2 * half + 1) * strip.scale_px;
  return left_px >= 0.0 && right_px <= static_cast<double>(image_width_);
}

void DisparityScan::scan(const FeatureMaps& left, const hal::Image& left_image,
                         PixelPoint left_fixation, const hal::Image& right,
                         PixelPoint right_fixation, DisparityScanResult& out) noexcept {
  out = DisparityScanResult{};
  if (!enabled_ || strip_->build_one_level(right, level_, right_fixation) != hal::Status::kOk ||
      left_context_->build_one_level(left_image, level_, left_fixation) != hal::Status::kOk) {
    return;
  }
  const RetinaLevelView strip = strip_->level(level_);
  // Only the features' families are computed; the bank writes map i at plane i.
  strip_bank_->apply(strip, required_, strip_maps_.data());
  context_bank_->apply(left_context_->level(level_), required_, context_maps_.data());
  const int scale = strip.scale_px;
  out.searched = true;
  out.level = level_;
  out.scale_px = scale;

  const float* left_level = left.level(level_);
  {
    const int cx = width_ / 2, cy = height_ / 2;
    const int n = (2 * half_ + 1) * (2 * half_y_ + 1);
    double variance = 0.0;
    for (const int f : features_) {
      const float* map = left_level + static_cast<std::ptrdiff_t>(f) * width_ * height_;
      double sum = 0.0, sum_sq = 0.0;
      for (int y = cy - half_y_; y <= cy + half_y_; ++y) {
        for (int x = cx - half_; x <= cx + half_; ++x) {
          sum += map[y * width_ + x];
          sum_sq += static_cast<double>(map[y * width_ + x]) * map[y * width_ + x];
        }
      }
      const double mean = sum / n;
      variance += std::max(0.0, sum_sq / n - mean * mean);
    }
    out.texture_rms =
        static_cast<float>(std::sqrt(variance / static_cast<double>(features_.size())));
  }

  for (int tier = 0; tier < kWindowTiers; ++tier) {
    const bool last = tier + 1 == kWindowTiers;
    const ProfileVerdict verdict = score_profile(tier, left_level, strip);
    if (!(verdict.decisive && verdict.localized) && !last) continue;
    out.count = 0;
    out.window_tier = tier;
    out.localized = verdict.localized;
    out.window_samples = (2 * tier_half(tier) + 1) * (2 * tier_half_y(tier) + 1);
    collect_candidates(tier, left_level, strip, out);
    // The scan's own window decides only if the next wider one does not clearly prefer another
    // peak: a patch that repeats nearby (a fine checker) can lead clearly at a wrong period,
    // which its outline refutes. Wider windows are not second-guessed by wider ones still:
    // those hold more of the surround than of a small object.
    bool context_agrees = true;
    for (int i = 1; i < out.count && tier == 0; ++i) {
      context_agrees = context_agrees && out.candidates[static_cast<std::size_t>(i)].context_score -
                                                 out.candidates[0].context_score <
                                             kDecisiveMargin;
    }
    if (context_agrees || last) return;
  }
}

DisparityScan::ProfileVerdict DisparityScan::score_profile(int tier, const float* left_level,
                                                           const RetinaLevelView& strip) noexcept {
  const int half = tier_half(tier);
  float best = kOutside;
  int best_shift = 0;
  for (int d = -range_; d <= range_; ++d) {
    float& s = scores_[static_cast<std::size_t>(d + range_)];
    s = inside(strip, d, half) ? score(tier, left_level, d) : kOutside;
    if (s > best) {
      best = s;
      best_shift = d;
    }
  }
  if (!(best > 0.0f)) return {};
  // The best local maximum of another disparity (not the best's neighbours). A plateau counts
  // as one: a profile that is flat (nothing varies along x) leads nowhere.
  float second = kOutside;
  for (int d = -range_ + 1; d < range_; ++d) {
    if (std::abs(d - best_shift) <= 1) continue;
    const float s = scores_[static_cast<std::size_t>(d + range_)];
    if (s >= scores_[static_cast<std::size_t>(d - 1 + range_)] &&
        s >= scores_[static_cast<std::size_t>(d + 1 + range_)]) {
      second = std::max(second, s);
    }
  }
  // Localized: the score falls away within kLocalizedFlank samples on both sides (a rounded
  // peak of coarse texture does; the lowest score of each flank counts, so a texture repeating
  // every other sample does too). Texture running almost along x (horizontal stripes seen
  // slightly askew, or with a little vertical disparity) scores a plateau of shifts alike, and
  // its highest point is set by the tilt, not by the depth.
  const auto at = [this](int d) {
    return d < -range_ || d > range_ ? kOutside : scores_[static_cast<std::size_t>(d + range_)];
  };
  float below = best;
  float above = best;
  for (int step = 1; step <= kLocalizedFlank; ++step) {
    below = std::min(below, at(best_shift - step));
    above = std::min(above, at(best_shift + step));
  }
  return {best - second >= kDecisiveMargin, best - std::max(below, above) >= kLocalizedDrop};
}

void DisparityScan::collect_candidates(int tier, const float* left_level,
                                       const RetinaLevelView& strip,
                                       DisparityScanResult& out) const noexcept {
  const int scale = strip.scale_px;
  const int context_tier = std::min(tier + 1, kWindowTiers - 1);
  const int context_half = tier_half(context_tier);
  out.shifts = 0;
  for (int d = -range_; d <= range_; ++d) {
    if (scores_[static_cast<std::size_t>(d + range_)] > kOutside) ++out.shifts;
  }
  // Local maxima (ties resolved toward the lower shift), best first; the range's ends only if
  // the scores fall toward them (the range covers every disparity the rig can produce).
  for (int d = -range_; d <= range_; ++d) {
    const float s = scores_[static_cast<std::size_t>(d + range_)];
    if (!(s > 0.0f)) continue;
    const float below = d > -range_ ? scores_[static_cast<std::size_t>(d - 1 + range_)] : kOutside;
    const float above = d < range_ ? scores_[static_cast<std::size_t>(d + 1 + range_)] : kOutside;
    // Beside a shift whose window leaves the strip, the scores must fall away from it: the
    // first shift of a plateau is no peak.
    const bool rises = below > kOutside ? s > below : s > above;
    if (!(rises && s >= above)) continue;
    // The context at the peak and its neighbours (the peak is on the scan's block grid); a
    // context window past the image's edge says nothing either way. The widest window is its
    // own context.
    float context = s;
    if (context_tier != tier && inside(strip, d, context_half)) {
      context = score(context_tier, left_level, d);
      if (d > -range_) context = std::max(context, score(context_tier, left_level, d - 1));
      if (d < range_) context = std::max(context, score(context_tier, left_level, d + 1));
    }
    // The peak between blocks: a parabola through it and its neighbours. Without it a fixated
    // surface whose finer levels hold too little texture to refine is measured to the nearest
    // block only (half a block is 2 px at the shipped retina: a 0.2 deg vergence error).
    double offset = 0.0;
    if (below > kOutside && above > kOutside) {
      const double curvature = below - 2.0 * s + above;
      if (curvature < 0.0) offset = std::clamp(0.5 * (below - above) / curvature, -0.5, 0.5);
    }
    const DisparityCandidate candidate{static_cast<float>((d + offset) * scale), s, context};
    int at = out.count;
    while (at > 0 && out.candidates[static_cast<std::size_t>(at - 1)].score < s) --at;
    if (at >= DisparityScanResult::kMaxCandidates) continue;
    const int last = std::min(out.count, DisparityScanResult::kMaxCandidates - 1);
    for (int i = last; i > at; --i) {
      out.candidates[static_cast<std::size_t>(i)] = out.candidates[static_cast<std::size_t>(i - 1)];
    }
    out.candidates[static_cast<std::size_t>(at)] = candidate;
    out.count = std::min(out.count + 1, DisparityScanResult::kMaxCandidates);
  }
}

}  // namespace cambio::perception
