#pragma once

// What perception-bench prints: one JSON object with the medians and ratios (--json) or a table
// for people. Every figure is the median time per stereo pair.

#include "ssm_timing.hpp"

namespace cambio::app {

/// The SSM variants measured, each on the benchmark pair.
struct SsmVariantFigures {
  SsmFigures paper;              ///< The paper's 4 x 16 x 16 retina, coarsest level widened; grey.
  SsmFigures paper_rgb;          ///< The same on rgb8 frames.
  SsmFigures paper_lens;         ///< `paper` read through a barrel lens's model.
  SsmFigures paper_moving;       ///< `paper` fixating a new place every run.
  SsmFigures paper_lens_moving;  ///< `paper_lens` fixating a new place every run.
  SsmFigures fovea_only;         ///< The paper's retina without the field-covering level.
  SsmFigures paper_fresh;        ///< `paper` with the caches flushed before each run.
  SsmFigures paper_rgb_fresh;    ///< `paper_rgb` with the caches flushed before each run.
  SsmFigures wide;               ///< 4 x 64 x 64, fovea only.
};

/// A memcpy of both images (the memory bound) alternated with the paper's SSM in rounds.
struct MemcpyRounds {
  double memcpy_us = 0;              ///< Median of the rounds' memcpy medians.
  double ssm_paper_over_memcpy = 0;  ///< Median of the rounds' ratios.
};

/// The paper's SSM with the whole-range disparity scan alternated with the paper's SSM in rounds.
struct ScanRounds {
  double scan_us = 0;            ///< Median of the rounds' medians, with the scan.
  double paper_us = 0;           ///< Median of the rounds' medians, without it.
  double scan_over_paper = 0;    ///< Median of the rounds' ratios.
  double disparity_part_us = 0;  ///< The scan SSM's last disparity part.
  double range_px = 0;           ///< The scan's range.
  float disparity_px = 0;        ///< The scan SSM's last disparity at the fovea.
  int window_tier = -1;          ///< The scan's deciding window on the last frame.
};

/// The fixated object's region (the zero-disparity filter, which pursuit asks for) alternated
/// with the paper's SSM in rounds: what asking for it adds to a frame.
struct RegionRounds {
  double region_us = 0;          ///< Median of the rounds' medians.
  double paper_us = 0;           ///< The paper's SSM, median of the rounds' medians.
  double region_over_paper = 0;  ///< Median of the rounds' ratios.
  int cells = 0;                 ///< Cells searched (cells x cells).
};

struct PerceptionBenchFigures {
  int repeats = 0;
  int rounds = 0;  ///< Rounds of each alternated comparison.
  SsmVariantFigures ssm;
  MemcpyRounds memcpy_rounds;
  ScanRounds scan_rounds;
  /// The same on horizontal stripes, where no window decides before the widest: the scan's
  /// worst case.
  ScanRounds widest_window_rounds;
  RegionRounds region_rounds;
  double opencv_filter_us = 0;  ///< The SSM's operator set on both whole images.
  double stereo_bm_us = 0;      ///< cv::StereoBM on the whole pair.
};

/// The figures as one JSON object on stdout.
void print_perception_bench_json(const PerceptionBenchFigures& figures);

/// The figures as a table on stdout.
void print_perception_bench_table(const PerceptionBenchFigures& figures);

}  // namespace cambio::app
