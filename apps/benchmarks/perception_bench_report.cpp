#include "perception_bench_report.hpp"

#include <cstdio>
#include <iostream>

#include "json_output.hpp"
#include "stereo_test_pair.hpp"

namespace cambio::app {

namespace {

Json parts_json(const perception::SsmTimings& t) {
  return Json{{"retina", as_printed(t.retina_us, "%.2f")},
              {"features", as_printed(t.features_us, "%.2f")},
              {"disparity", as_printed(t.disparity_us, "%.2f")},
              {"motion", as_printed(t.motion_us, "%.2f")},
              {"moments", as_printed(t.moments_us, "%.2f")}};
}

void print_ssm(const char* name, const SsmFigures& f) {
  std::printf(
      "  %-28s%10.1f us   (retina %.1f, features %.1f, disparity %.1f, motion %.1f, "
      "moments %.1f)\n",
      name, f.total_us, f.parts.retina_us, f.parts.features_us, f.parts.disparity_us,
      f.parts.motion_us, f.parts.moments_us);
}

}  // namespace

void print_perception_bench_json(const PerceptionBenchFigures& figures) {
  const SsmVariantFigures& ssm = figures.ssm;
  const ScanRounds& scan = figures.scan_rounds;
  const ScanRounds& widest = figures.widest_window_rounds;
  const Json json = {
      {"image", "640x480 stereo pair, grey8 (and rgb8 for ssm_paper_rgb)"},
      {"threads", 1},
      {"repeats", figures.repeats},
      {"ssm_paper_us", as_printed(ssm.paper.total_us, "%.2f")},
      {"ssm_paper_rgb_us", as_printed(ssm.paper_rgb.total_us, "%.2f")},
      {"ssm_paper_lens_us", as_printed(ssm.paper_lens.total_us, "%.2f")},
      {"ssm_paper_lens_over_ssm_paper",
       as_printed(ssm.paper_lens.total_us / ssm.paper.total_us, "%.2f")},
      {"ssm_paper_moving_us", as_printed(ssm.paper_moving.total_us, "%.2f")},
      {"ssm_paper_lens_moving_us", as_printed(ssm.paper_lens_moving.total_us, "%.2f")},
      {"ssm_paper_lens_moving_over_ssm_paper_moving",
       as_printed(ssm.paper_lens_moving.total_us / ssm.paper_moving.total_us, "%.2f")},
      {"ssm_fovea_only_us", as_printed(ssm.fovea_only.total_us, "%.2f")},
      {"ssm_paper_fresh_us", as_printed(ssm.paper_fresh.total_us, "%.2f")},
      {"ssm_paper_rgb_fresh_us", as_printed(ssm.paper_rgb_fresh.total_us, "%.2f")},
      {"ssm_64_us", as_printed(ssm.wide.total_us, "%.2f")},
      {"memcpy_us", as_printed(figures.memcpy_rounds.memcpy_us, "%.2f")},
      {"opencv_full_filter_us", as_printed(figures.opencv_filter_us, "%.1f")},
      {"opencv_stereo_bm_us", as_printed(figures.stereo_bm_us, "%.1f")},
      {"opencv_full_filter_over_ssm_paper",
       as_printed(figures.opencv_filter_us / ssm.paper.total_us, "%.1f")},
      {"ssm_paper_over_memcpy", as_printed(figures.memcpy_rounds.ssm_paper_over_memcpy, "%.2f")},
      {"ssm_paper_over_memcpy_rounds", figures.rounds},
      {"ssm_paper_rgb_over_ssm_paper",
       as_printed(ssm.paper_rgb.total_us / ssm.paper.total_us, "%.2f")},
      {"ssm_paper_retina_over_fovea_only_retina",
       as_printed(ssm.paper.parts.retina_us / ssm.fovea_only.parts.retina_us, "%.2f")},
      {"ssm_paper_rgb_retina_over_ssm_paper_retina",
       as_printed(ssm.paper_rgb.parts.retina_us / ssm.paper.parts.retina_us, "%.2f")},
      {"opencv_full_filter_over_ssm_64",
       as_printed(figures.opencv_filter_us / ssm.wide.total_us, "%.1f")},
      {"ssm_64_over_memcpy",
       as_printed(ssm.wide.total_us / figures.memcpy_rounds.memcpy_us, "%.2f")},
      {"opencv_stereo_bm_over_ssm_paper",
       as_printed(figures.stereo_bm_us / ssm.paper.total_us, "%.1f")},
      {"ssm_paper_parts_us", parts_json(ssm.paper.parts)},
      {"ssm_paper_rgb_parts_us", parts_json(ssm.paper_rgb.parts)},
      {"ssm_paper_lens_parts_us", parts_json(ssm.paper_lens.parts)},
      {"ssm_paper_lens_moving_parts_us", parts_json(ssm.paper_lens_moving.parts)},
      {"ssm_paper_fresh_parts_us", parts_json(ssm.paper_fresh.parts)},
      {"ssm_paper_rgb_fresh_parts_us", parts_json(ssm.paper_rgb_fresh.parts)},
      {"ssm_fovea_only_parts_us", parts_json(ssm.fovea_only.parts)},
      {"ssm_64_parts_us", parts_json(ssm.wide.parts)},
      {"ssm_paper_disparity_px", as_printed(ssm.paper.disparity_px, "%.3f")},
      {"ssm_fovea_only_disparity_px", as_printed(ssm.fovea_only.disparity_px, "%.3f")},
      {"ssm_64_disparity_px", as_printed(ssm.wide.disparity_px, "%.3f")},
      {"ssm_paper_scan_us", as_printed(scan.scan_us, "%.2f")},
      {"ssm_paper_in_scan_rounds_us", as_printed(scan.paper_us, "%.2f")},
      {"ssm_paper_scan_over_ssm_paper", as_printed(scan.scan_over_paper, "%.2f")},
      {"ssm_paper_scan_disparity_part_us", as_printed(scan.disparity_part_us, "%.2f")},
      {"ssm_paper_scan_range_px", as_printed(scan.range_px, "%.1f")},
      {"ssm_paper_scan_disparity_px", as_printed(scan.disparity_px, "%.3f")},
      {"ssm_paper_scan_window_tier", scan.window_tier},
      // The scan's worst case: horizontal stripes, every window tried up to the widest.
      {"ssm_paper_scan_widest_window_us", as_printed(widest.scan_us, "%.2f")},
      {"ssm_paper_on_stripes_us", as_printed(widest.paper_us, "%.2f")},
      {"ssm_paper_scan_widest_window_over_ssm_paper", as_printed(widest.scan_over_paper, "%.2f")},
      {"ssm_paper_scan_widest_window_disparity_part_us",
       as_printed(widest.disparity_part_us, "%.2f")},
      {"ssm_paper_scan_widest_window_tier", widest.window_tier},
      // The fixated region (zero-disparity filter), asked for while fixating and pursuing.
      {"fixated_region_us", as_printed(figures.region_rounds.region_us, "%.2f")},
      {"ssm_paper_in_region_rounds_us", as_printed(figures.region_rounds.paper_us, "%.2f")},
      {"fixated_region_over_ssm_paper",
       as_printed(figures.region_rounds.region_over_paper, "%.2f")},
      {"fixated_region_cells", figures.region_rounds.cells},
      {"true_disparity_px", kBenchPairDisparityPx}};
  std::cout << json_text(json);
}

void print_perception_bench_table(const PerceptionBenchFigures& figures) {
  const SsmVariantFigures& ssm = figures.ssm;
  const double paper_vs_filter = figures.opencv_filter_us / ssm.paper.total_us;
  const double wide_vs_filter = figures.opencv_filter_us / ssm.wide.total_us;
  const double wide_vs_memcpy = ssm.wide.total_us / figures.memcpy_rounds.memcpy_us;
  std::printf("perception-bench: 640x480 stereo pair, one thread, medians per pair\n");
  print_ssm("SSM paper (grey)", ssm.paper);
  print_ssm("SSM paper (rgb8)", ssm.paper_rgb);
  print_ssm("SSM paper through a lens", ssm.paper_lens);
  print_ssm("SSM paper, fovea moving", ssm.paper_moving);
  print_ssm("SSM lens, fovea moving", ssm.paper_lens_moving);
  print_ssm("SSM fovea only (grey)", ssm.fovea_only);
  print_ssm("SSM paper, fresh frames", ssm.paper_fresh);
  print_ssm("SSM paper (rgb8), fresh", ssm.paper_rgb_fresh);
  print_ssm("SSM 4 x 64 x 64 (fovea)", ssm.wide);
  std::printf(
      "  SSM paper + disparity scan  %10.1f us   (+-%.0f px; %.2fx the paper SSM, median of %d "
      "alternating rounds)\n",
      figures.scan_rounds.scan_us, figures.scan_rounds.range_px,
      figures.scan_rounds.scan_over_paper, figures.rounds);
  std::printf(
      "  ... on horizontal stripes   %10.1f us   (every window up to the widest, tier %d; %.2fx "
      "the paper SSM on them)\n",
      figures.widest_window_rounds.scan_us, figures.widest_window_rounds.window_tier,
      figures.widest_window_rounds.scan_over_paper);
  std::printf(
      "  fixated region (ZDF)        %10.1f us   (%d x %d cells; %.2fx the paper SSM, median of %d "
      "alternating rounds)\n",
      figures.region_rounds.region_us, figures.region_rounds.cells, figures.region_rounds.cells,
      figures.region_rounds.region_over_paper, figures.rounds);
  std::printf("  memcpy of both images       %10.1f us   (median of %d rounds)\n",
              figures.memcpy_rounds.memcpy_us, figures.rounds);
  std::printf("  OpenCV full-image filters   %10.1f us   (same operator set, cv::sepFilter2D)\n",
              figures.opencv_filter_us);
  std::printf("  OpenCV StereoBM full pair   %10.1f us\n", figures.stereo_bm_us);
  std::printf(
      "  paper SSM: %.0fx faster than full-image filtering, %.2fx a memcpy (median of %d "
      "alternating rounds)\n",
      paper_vs_filter, figures.memcpy_rounds.ssm_paper_over_memcpy, figures.rounds);
  std::printf("  64x64 SSM: %.0fx faster than full-image filtering, %.2fx a memcpy\n",
              wide_vs_filter, wide_vs_memcpy);
  std::printf("  disparity at the fovea: %.3f px (paper), %.3f px (64x64); true 3.3 px\n",
              static_cast<double>(ssm.paper.disparity_px),
              static_cast<double>(ssm.wide.disparity_px));
}

}  // namespace cambio::app
