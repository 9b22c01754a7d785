#include "cambio/perception/disparity_estimator.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "cambio/perception/window_x_structure.hpp"
#include "cambio/perception/window_zncc.hpp"

namespace cambio::perception {

DisparityEstimator::DisparityEstimator(const DisparityConfig& config, const OperatorBank& bank,
                                       int width, int height)
    : config_(config), width_(width), height_(height) {
  for (const auto& name : config.features) {
    const int index = bank.find(name);
    if (index < 0) throw std::invalid_argument("disparity feature '" + name + "' is not a map");
    features_.push_back(index);
    required_ |= MapMask{1} << index;
  }
  if (features_.empty()) throw std::invalid_argument("disparity needs at least one feature map");
  half_ = config.window_half_px > 0 ? config.window_half_px : std::max(1, width / 4);
  half_y_ = std::min(half_, (height - 1) / 2);
  if (2 * half_ + 1 > width) {
    throw std::invalid_argument("disparity window is wider than the retina");
  }
  // The widest search: the coarsest level's range at block size 1, or a refinement (<= width),
  // plus refine_range_px shifts of extension on each side.
  scores_.assign(static_cast<std::size_t>(
                     2 * std::max(width, static_cast<int>(std::ceil(config.search_range_px))) +
                     4 * std::max(config.refine_range_px, 0) + 1),
                 0.0f);
}

float DisparityEstimator::left_texture(const float* left) const noexcept {
  const int cx = width_ / 2;
  const int cy = height_ / 2;
  const int n = (2 * half_ + 1) * (2 * half_y_ + 1);
  double variance = 0.0;
  for (const int f : features_) {
    const float* map = plane(left, f);
    double sum = 0.0;
    double sum_sq = 0.0;
    for (int y = cy - half_y_; y <= cy + half_y_; ++y) {
      for (int x = cx - half_; x <= cx + half_; ++x) {
        const double v = map[y * width_ + x];
        sum += v;
        sum_sq += v * v;
      }
    }
    const double mean = sum / n;
    variance += std::max(0.0, sum_sq / n - mean * mean);
  }
  return static_cast<float>(std::sqrt(variance / static_cast<double>(features_.size())));
}

float DisparityEstimator::score(const float* left, const float* right, int shift) const noexcept {
  // x_right = x_left - d: the right window `shift` samples left of the centre.
  return window_zncc(left, width_, width_ / 2, right, width_, width_ / 2 - shift, height_ / 2,
                     height_, half_, half_y_, features_);
}

void DisparityEstimator::estimate(const FeatureMaps& left, const FeatureMaps& right,
                                  const Retina& left_retina, const Retina& right_retina,
                                  DisparityResult& out, ShiftedLevelSource* shifted,
                                  const DisparityScanResult* scan) const noexcept {
  out = DisparityResult{};
  out.levels = left_retina.levels();
  if (scan == nullptr || !scan->searched || scan->count == 0 || scan->level < 0 ||
      scan->level >= left_retina.levels()) {
    descend(left, right, left_retina, right_retina, left_retina.levels() - 1, false, 0.0, 0, out,
            shifted);
  } else {
    const CandidateEvidence best =
        refine_candidates(left, right, left_retina, right_retina, *scan, out, shifted);
    out.candidates = scan->count;
    out.confidence =
        scan_confidence(best, runner_up_key(*scan, out.disparity_px), scan->window_samples);
  }
  // After the descent and the refinements, which write the whole result.
  if (scan != nullptr && scan->searched) out.scan_window_tier = scan->window_tier;
}

DisparityEstimator::CandidateEvidence DisparityEstimator::refine_candidates(
    const FeatureMaps& left, const FeatureMaps& right, const Retina& left_retina,
    const Retina& right_retina, const DisparityScanResult& scan, DisparityResult& out,
    ShiftedLevelSource* shifted) const noexcept {
  // Every candidate of the scan is refined through the finer levels; the one the fixated patch
  // agrees with best (the scan's score plus the finer levels' peaks) wins. A wrong candidate
  // (a backdrop, a repeated texture) finds no peak at the finer levels, whose windows hold the
  // fixated surface alone.
  CandidateEvidence best;
  for (int i = 0; i < scan.count; ++i) {
    const DisparityCandidate& candidate = scan.candidates[static_cast<std::size_t>(i)];
    descend_from_candidate(left, right, left_retina, right_retina, scan, candidate, out.levels,
                           shifted);
    const CandidateEvidence evidence = weigh_candidate(scan, candidate, trial_);
    keys_[static_cast<std::size_t>(i)] = evidence.key;
    refined_[static_cast<std::size_t>(i)] = trial_.disparity_px;
    if (evidence.key > best.key) {
      best = evidence;
      out = trial_;
    }
  }
  return best;
}

void DisparityEstimator::descend_from_candidate(const FeatureMaps& left, const FeatureMaps& right,
                                                const Retina& left_retina,
                                                const Retina& right_retina,
                                                const DisparityScanResult& scan,
                                                const DisparityCandidate& candidate, int levels,
                                                ShiftedLevelSource* shifted) const noexcept {
  DisparityResult& trial = trial_;
  trial = DisparityResult{};
  trial.levels = levels;
  // The scan's level holds the candidate as if this estimator had found it there.
  LevelDisparity& scanned = trial.per_level[static_cast<std::size_t>(scan.level)];
  scanned.searched = true;
  scanned.valid = true;
  scanned.disparity_px = candidate.disparity_px;
  scanned.peak_score = candidate.score;
  scanned.texture_rms = scan.texture_rms;
  scanned.scale_px = scan.scale_px;
  trial.valid = true;
  trial.disparity_px = candidate.disparity_px;
  trial.level = scan.level;
  descend(left, right, left_retina, right_retina, scan.level - 1, true, candidate.disparity_px,
          scan.scale_px, trial, shifted, /*from_scan=*/true);
}

DisparityEstimator::CandidateEvidence DisparityEstimator::weigh_candidate(
    const DisparityScanResult& scan, const DisparityCandidate& candidate,
    const DisparityResult& trial) const noexcept {
  CandidateEvidence evidence;
  evidence.key = candidate.score + candidate.context_score;
  evidence.weight = 2.0f;
  evidence.texture = scan.texture_rms;
  evidence.localized = scan.localized;
  for (int k = scan.level - 1; k >= 0; --k) {
    const LevelDisparity& level = trial.per_level[static_cast<std::size_t>(k)];
    if (!level.searched || level.aperture || level.texture_rms < config_.min_texture_rms) continue;
    evidence.localized = evidence.localized || (level.valid && !level.at_range_edge);
    // The finer levels' windows are smaller (a 9-px window at level 0 may see one smooth
    // texel): they tip the balance between candidates the scan finds alike, not more.
    evidence.key += kFinerLevelWeight * (level.valid ? level.peak_score : 0.0f);
    evidence.weight += kFinerLevelWeight;
    evidence.texture = std::max(evidence.texture, level.texture_rms);
  }
  return evidence;
}

float DisparityEstimator::runner_up_key(const DisparityScanResult& scan,
                                        float winner_px) const noexcept {
  // The runner-up is the best hypothesis of another disparity: candidates that refined to the
  // winner's (neighbouring maxima of one textured surface) are the same hypothesis.
  float second_key = -1e9f;
  for (int i = 0; i < scan.count; ++i) {
    const auto at = static_cast<std::size_t>(i);
    if (std::abs(refined_[at] - winner_px) > 1.5f * static_cast<float>(scan.scale_px)) {
      second_key = std::max(second_key, keys_[at]);
    }
  }
  return second_key;
}

float DisparityEstimator::scan_confidence(const CandidateEvidence& best, float second_key,
                                          int window_samples) const noexcept {
  // Confidence, on the evidence the choice was made on: how well the winner matches (its mean
  // score per unit weight), how clearly it beats the best hypothesis of another disparity (a
  // periodic texture gives several alike: low), and whether there was texture to match at all
  // (the most textured level compared: a fine texture averages out at the scan's blocks).
  // A wider deciding window's scores vary less between shifts of alike patches (sampling noise
  // falls as one over the root of the samples): the lead that makes it distinct shrinks so.
  const double quality = std::clamp(best.key / best.weight, 0.0f, 1.0f);
  const double margin = second_key <= -1e8f ? quality : (best.key - second_key) / best.weight;
  const double own_samples = (2.0 * half_ + 1.0) * (2.0 * half_y_ + 1.0);
  const double distinct_margin =
      kDistinctMargin * std::sqrt(own_samples / std::max<double>(window_samples, own_samples));
  const double ratio = best.texture / config_.min_texture_rms;
  const double texture_factor = ratio * ratio / (1.0 + ratio * ratio);
  // A disparity no window pinned down (the scan's widest scored a plateau, no finer level
  // could match) is the tilt of texture running along x, not a depth: right by chance only.
  const double localization = best.localized ? 1.0 : kUnlocalizedShare;
  return static_cast<float>(quality * quality * std::clamp(margin / distinct_margin, 0.0, 1.0) *
                            texture_factor * localization);
}

void DisparityEstimator::descend(const FeatureMaps& left, const FeatureMaps& right,
                                 const Retina& left_retina, const Retina& right_retina,
                                 int from_level, bool have_estimate, double estimate_px,
                                 int coarser_scale, DisparityResult& out,
                                 ShiftedLevelSource* shifted, bool from_scan) const noexcept {
  const int cx = width_ / 2;
  // Shifts d keep the right window inside the map: right columns cx - h - d .. cx + h - d.
  const int shift_min = cx + half_ - (width_ - 1);
  const int shift_max = cx - half_;
  for (int k = from_level; k >= 0; --k) {
    LevelDisparity& level = out.per_level[static_cast<std::size_t>(k)];
    const int scale = left_retina.level(k).scale_px;
    level.scale_px = scale;
    if (right_retina.level(k).scale_px != scale) continue;  // Field-covering levels that differ.
    const float* left_maps = left.level(k);
    int lo = 0;
    int hi = 0;
    int centre = 0;
    bool widened = false;
    if (!have_estimate) {
      const int range = static_cast<int>(std::ceil(config_.search_range_px / scale));
      lo = -range;
      hi = range;
    } else {
      // refine_range_px finer px around the estimate for an octave step; a field-covering
      // coarsest level can be many octaves coarser, and its uncertainty grows with the ratio.
      const int ratio = std::max(1, coarser_scale / scale);
      int range = std::max(config_.refine_range_px, (config_.refine_range_px * ratio + 1) / 2);
      // The scan's window is wide enough to hold a near curved object's outline, whose disparity
      // is no surface point's (each eye sees its own occluding contour: a 3-cm ball 0.7 m away
      // has them 5 px apart), and on a fine periodic texture the finer levels would lock onto
      // the alias within their range: the first level below the scan searches one scan block
      // further each way.
      widened = from_scan;
      if (widened) range += ratio;
      range = std::min(range, width_);
      from_scan = false;
      centre = static_cast<int>(std::lround(estimate_px / scale));
      lo = centre - range;
      hi = centre + range;
    }
    // The coarsest search stays inside the overlap (moving a coarse window costs a large source
    // footprint); refinements may move the right window, if there is a source for it.
    if (!have_estimate || shifted == nullptr) {
      lo = std::max(lo, shift_min);
      hi = std::min(hi, shift_max);
    }
    // The coarser estimate does not fit this level's overlap of the two retinas: keep it.
    if (lo > hi) break;
    level.texture_rms = left_texture(left_maps);
    level.x_structure =
        window_x_structure(left_maps, width_, cx, height_ / 2, height_, half_, half_y_, features_);
    level.aperture = level.x_structure < DisparityScan::kMinXStructure;
    if (level.texture_rms < config_.min_texture_rms || level.aperture) {
      level.searched = true;
      level.search_min_px = lo;
      level.search_max_px = hi;
      continue;
    }

    // Shifts beyond the overlap move the right window (by `window` level px) so that the shift
    // scored against it, d - window, is inside [shift_min, shift_max]; moved windows sample the
    // same block grid, so every score is the same ZNCC as with a wider right retina.
    const float* right_maps = right.level(k);
    int window = 0;
    const int base = lo - config_.refine_range_px;  // scores_[d - base]; room to extend below.
    const auto score_shift = [&](int d) {
      if (d - window < shift_min || d - window > shift_max) {
        const bool inside = d >= shift_min && d <= shift_max;
        const float* maps = inside               ? right.level(k)
                            : shifted != nullptr ? shifted->shifted_right_level(k, d - shift_min)
                                                 : nullptr;
        if (maps == nullptr) return false;
        right_maps = maps;
        window = inside ? 0 : d - shift_min;
        if (!inside) ++level.moved_windows;
      }
      scores_[static_cast<std::size_t>(d - base)] = score(left_maps, right_maps, d - window);
      return true;
    };
    const auto at = [this, base](int d) { return scores_[static_cast<std::size_t>(d - base)]; };
    int best = lo;
    for (int d = lo; d <= hi; ++d) {
      if (!score_shift(d)) {
        hi = d - 1;
        break;
      }
      if (at(d) > at(best)) best = d;
    }
    if (lo > hi) break;
    // A refinement whose best match sits on its range's edge may be a coarser estimate that was
    // off by a little more than the range allows: extend towards it, up to refine_range_px more
    // shifts, while the scores keep rising.
    if (have_estimate) {
      for (int step = 0; step < config_.refine_range_px && (best == lo || best == hi); ++step) {
        const int d = best == hi ? hi + 1 : lo - 1;
        if (!score_shift(d)) break;
        (d > hi ? hi : lo) = d;
        if (at(d) > at(best)) best = d;
      }
    }
    // In the widened range a periodic texture has alike peaks a period apart: the one nearest
    // the scan's estimate stands unless another is decisively better (the scan's bias corrected,
    // not an alias taken).
    if (widened) {
      int nearest = best;
      for (int d = lo; d <= hi; ++d) {
        const bool peak = (d == lo || at(d) >= at(d - 1)) && (d == hi || at(d) >= at(d + 1));
        if (peak && std::abs(d - centre) < std::abs(nearest - centre)) nearest = d;
      }
      if (at(best) - at(nearest) < DisparityScan::kDecisiveMargin) best = nearest;
    }
    level.searched = true;
    level.search_min_px = lo;
    level.search_max_px = hi;
    const float peak = at(best);
    float second = -1.0f;
    for (int d = lo; d <= hi; ++d) {
      if (std::abs(d - best) > 1) second = std::max(second, at(d));
    }
    double offset = 0.0;
    level.at_range_edge = best == lo || best == hi;
    if (!level.at_range_edge) {
      // Parabola through (best-1, best, best+1); its vertex is the sub-pixel peak.
      const double minus = at(best - 1);
      const double plus = at(best + 1);
      const double curvature = minus - 2.0 * peak + plus;
      if (curvature < 0.0) offset = std::clamp(0.5 * (minus - plus) / curvature, -0.5, 0.5);
    }
    const double ratio = level.texture_rms / config_.min_texture_rms;
    const double texture_factor = ratio * ratio / (1.0 + ratio * ratio);
    const double distinct = second <= -1.0f ? 1.0 : std::clamp((peak - second) / 0.25, 0.0, 1.0);
    level.peak_score = peak;
    level.disparity_px = static_cast<float>((best + offset) * scale);
    level.confidence = static_cast<float>(std::max(0.0f, peak) * distinct * texture_factor);
    // A best match on the edge of the range may be a slope towards a peak outside it (e.g. a
    // disparity beyond what this level's overlap allows). With a coarser estimate, keep that
    // and stop; without one, report the edge at half confidence and refine no further.
    level.valid = peak > 0.0f && !(level.at_range_edge && have_estimate);
    if (level.at_range_edge) level.confidence *= 0.5f;
    if (!level.valid) {
      if (level.at_range_edge) break;
      continue;
    }
    have_estimate = true;
    estimate_px = level.disparity_px;
    coarser_scale = scale;
    out.valid = true;
    out.disparity_px = level.disparity_px;
    out.confidence = level.confidence;
    out.level = k;
    if (level.at_range_edge) break;
  }
}

}  // namespace cambio::perception
