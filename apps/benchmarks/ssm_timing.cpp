#include "ssm_timing.hpp"

#include <unistd.h>

#include <algorithm>
#include <cstddef>
#include <optional>
#include <stdexcept>
#include <vector>

#include "bench_timing.hpp"

namespace cambio::app {

namespace {

/// Pushes the frames out of every cache level. Writes twice the last-level cache (64 MiB where
/// the size is unknown).
class CacheEvictor {
 public:
  CacheEvictor() {
    const long llc = sysconf(_SC_LEVEL3_CACHE_SIZE);
    buffer_.assign(llc > 0 ? 2 * static_cast<std::size_t>(llc) : std::size_t{64} << 20, 0);
  }
  void evict() {
    for (std::size_t i = 0; i < buffer_.size(); i += 64) buffer_[i] = static_cast<char>(i);
    asm volatile("" : : "r"(buffer_.data()) : "memory");
  }

 private:
  std::vector<char> buffer_;
};

/// The median of each part's times over the runs (the upper middle one for an even count).
perception::SsmTimings median_parts(const std::vector<perception::SsmTimings>& parts) {
  const auto median_of_part = [&](double perception::SsmTimings::*field) {
    std::vector<double> values;
    for (const auto& p : parts) values.push_back(p.*field);
    std::nth_element(values.begin(),
                     values.begin() + static_cast<std::ptrdiff_t>(values.size() / 2), values.end());
    return values[values.size() / 2];
  };
  return {median_of_part(&perception::SsmTimings::retina_us),
          median_of_part(&perception::SsmTimings::features_us),
          median_of_part(&perception::SsmTimings::disparity_us),
          median_of_part(&perception::SsmTimings::motion_us),
          median_of_part(&perception::SsmTimings::moments_us),
          median_of_part(&perception::SsmTimings::total_us)};
}

}  // namespace

SsmRun::SsmRun(const perception::SsmConfig& config, const hal::Image& left, const hal::Image& right,
               const perception::LensDistortion* lens, Fixations fixations)
    : servo_(config, left.width_px, left.height_px),
      frame_(servo_.make_frame()),
      left_(left),
      right_(right),
      fixations_(fixations) {
  if (lens != nullptr) servo_.set_lenses(*lens, *lens);
}

const perception::SsmFrame& SsmRun::run() {
  perception::PixelPoint fixation{left_.width_px / 2, left_.height_px / 2};
  if (fixations_ == Fixations::kNewEveryRun) {
    // Around the centre, never the same place twice in a row nor within a few runs.
    constexpr int kPlaces = 7;
    const int place = runs_++ % kPlaces;
    fixation.x += (place - kPlaces / 2) * 9;
    fixation.y += (place % 3 - 1) * 7;
  }
  if (servo_.process(left_, right_, fixation, fixation, perception::FeatureRequest{}, frame_) !=
      hal::Status::kOk) {
    throw std::runtime_error("SSM rejected the benchmark pair");
  }
  return frame_;
}

SsmFigures time_ssm(const perception::SsmConfig& config, const hal::Image& left,
                    const hal::Image& right, int repeats, Frames frames,
                    const perception::LensDistortion* lens, Fixations fixations) {
  SsmRun ssm(config, left, right, lens, fixations);
  // Every run's parts, the untimed warm-up runs' included.
  std::vector<perception::SsmTimings> parts;
  parts.reserve(static_cast<std::size_t>(repeats) * 2);
  SsmFigures figures;
  std::optional<CacheEvictor> evictor;
  if (frames == Frames::kFresh) evictor.emplace();
  figures.total_us = median_us(
      repeats, [&] { parts.push_back(ssm.run().summary.timings); },
      [&] {
        if (evictor) evictor->evict();
      });
  figures.parts = median_parts(parts);
  figures.disparity_px = ssm.frame().summary.disparity.disparity_px;
  figures.confidence = ssm.frame().summary.disparity.confidence;
  return figures;
}

}  // namespace cambio::app
