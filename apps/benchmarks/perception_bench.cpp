#include "perception_bench.hpp"

#include <algorithm>
#include <cstring>
#include <vector>

#include <opencv2/core.hpp>

#include "bench_timing.hpp"
#include "cambio/perception/sensory_servo.hpp"
#include "command.hpp"
#include "opencv_baselines.hpp"
#include "perception_bench_report.hpp"
#include "ssm_timing.hpp"
#include "stereo_test_pair.hpp"

namespace cambio::app {

namespace {

/// Rounds of each alternated comparison; odd, so each median is one round's figure.
constexpr int kRounds = 11;

/// The retinas compared.
struct SsmConfigs {
  perception::SsmConfig paper;
  perception::SsmConfig fovea_only;
  perception::SsmConfig wide;
};

// The paper's retina: 4 x 16 x 16, its coarsest level widened to cover the whole field;
// sigmas 1.4, 2.7, 4, s = ceil(3 sigma).
SsmConfigs bench_ssm_configs() {
  SsmConfigs configs;
  configs.paper.retina.coarsest_covers_field = true;
  configs.fovea_only = configs.paper;  // Coarsest level 8 px blocks, 128 px wide.
  configs.fovea_only.retina.coarsest_covers_field = false;
  configs.wide = configs.fovea_only;
  configs.wide.retina.width_px = 64;
  configs.wide.retina.height_px = 64;
  return configs;
}

SsmVariantFigures time_ssm_variants(const SsmConfigs& configs, const BenchStereoPair& pair,
                                    int repeats) {
  SsmVariantFigures figures;
  figures.paper = time_ssm(configs.paper, pair.left, pair.right, repeats);
  // The same through a wide-angle lens's model (barrel, as calibrate stereo finds on OpenCV's
  // sample views): the retinas read the ideal image from the distorted one.
  const double focal_px = 554.256 * pair.left.width_px / 640.0;
  const perception::LensDistortion lens(
      hal::CameraIntrinsics{pair.left.width_px, pair.left.height_px, focal_px, focal_px,
                            0.5 * (pair.left.width_px - 1), 0.5 * (pair.left.height_px - 1)},
      hal::PlumbBobDistortion{-0.28, 0.07, 0.001, -0.0005, 0.0});
  figures.paper_lens =
      time_ssm(configs.paper, pair.left, pair.right, repeats, Frames::kWarm, &lens);
  // A new fixation every run: through a lens, every level's footprints are planned anew.
  figures.paper_moving = time_ssm(configs.paper, pair.left, pair.right, repeats, Frames::kWarm,
                                  nullptr, Fixations::kNewEveryRun);
  figures.paper_lens_moving = time_ssm(configs.paper, pair.left, pair.right, repeats, Frames::kWarm,
                                       &lens, Fixations::kNewEveryRun);
  figures.paper_rgb = time_ssm(configs.paper, pair.left_rgb, pair.right_rgb, repeats);
  figures.fovea_only = time_ssm(configs.fovea_only, pair.left, pair.right, repeats);
  // Eviction takes milliseconds a run: fewer repeats.
  const int fresh_repeats = std::max(5, repeats / 5);
  figures.paper_fresh =
      time_ssm(configs.paper, pair.left, pair.right, fresh_repeats, Frames::kFresh);
  figures.paper_rgb_fresh =
      time_ssm(configs.paper, pair.left_rgb, pair.right_rgb, fresh_repeats, Frames::kFresh);
  figures.wide = time_ssm(configs.wide, pair.left, pair.right, std::max(5, repeats / 5));
  return figures;
}

// The memory bound, alternated with the paper's SSM in short rounds: the ratio is the median of
// the rounds' ratios, so a burst of load from another process skews one round, not the figure
// (as sim-bench does for rendering).
MemcpyRounds time_memcpy_rounds(const BenchStereoPair& pair, SsmRun& paper_run, int per_round) {
  hal::Image left_copy = pair.left;
  hal::Image right_copy = pair.right;
  const auto copy_both = [&] {
    std::memcpy(left_copy.pixels.data(), pair.left.pixels.data(), pair.left.pixels.size());
    std::memcpy(right_copy.pixels.data(), pair.right.pixels.data(), pair.right.pixels.size());
    asm volatile("" : : "r"(left_copy.pixels.data()), "r"(right_copy.pixels.data()) : "memory");
  };
  std::vector<double> memcpy_round_us;
  std::vector<double> ratios;
  for (int round = 0; round < kRounds; ++round) {
    const double copy_us = median_us(per_round, copy_both);
    const double ssm_us = median_us(per_round, [&] { (void)paper_run.run(); });
    memcpy_round_us.push_back(copy_us);
    ratios.push_back(ssm_us / copy_us);
  }
  return {median_of(memcpy_round_us), median_of(ratios)};
}

// The paper's SSM with the whole-range disparity scan, as a run on the shipped head uses it (the
// range f b / 0.3 m), alternated round by round with the paper's SSM without it.
ScanRounds time_scan_rounds(const perception::SsmConfig& paper, const BenchStereoPair& pair,
                            SsmRun& paper_run, int per_round) {
  constexpr double kShippedHeadFocal_px = 554.256;
  constexpr double kShippedHeadBaseline_m = 0.12;
  perception::SsmConfig paper_scan = paper;
  paper_scan.disparity.scan_range_px =
      perception::largest_disparity_px(kShippedHeadFocal_px, kShippedHeadBaseline_m);
  SsmRun scan_run(paper_scan, pair.left, pair.right);
  std::vector<double> paper_round_us;
  std::vector<double> scan_round_us;
  std::vector<double> scan_ratios;
  for (int round = 0; round < kRounds; ++round) {
    const double paper_us = median_us(per_round, [&] { (void)paper_run.run(); });
    const double scan_us = median_us(per_round, [&] { (void)scan_run.run(); });
    paper_round_us.push_back(paper_us);
    scan_round_us.push_back(scan_us);
    scan_ratios.push_back(scan_us / paper_us);
  }
  ScanRounds figures;
  figures.scan_us = median_of(scan_round_us);
  figures.paper_us = median_of(paper_round_us);
  figures.scan_over_paper = median_of(scan_ratios);
  figures.disparity_part_us = scan_run.frame().summary.timings.disparity_us;
  figures.range_px = paper_scan.disparity.scan_range_px;
  figures.disparity_px = scan_run.frame().summary.disparity.disparity_px;
  figures.window_tier = scan_run.frame().summary.disparity.scan_window_tier;
  return figures;
}

// The fixated region's zero-disparity filter, alternated round by round with the paper's SSM.
RegionRounds time_region_rounds(const perception::SsmConfig& paper, const BenchStereoPair& pair,
                                SsmRun& paper_run, int per_round) {
  perception::ZeroDisparityFilter filter(paper.region);
  perception::FixatedRegion region;
  const perception::PixelPoint centre{pair.left.width_px / 2, pair.left.height_px / 2};
  std::vector<double> paper_round_us;
  std::vector<double> region_round_us;
  std::vector<double> ratios;
  for (int round = 0; round < kRounds; ++round) {
    const double paper_us = median_us(per_round, [&] { (void)paper_run.run(); });
    const double region_us = median_us(per_round, [&] {
      filter.find(pair.left, centre, pair.right, centre, region);
      asm volatile("" : : "r"(&region) : "memory");
    });
    paper_round_us.push_back(paper_us);
    region_round_us.push_back(region_us);
    ratios.push_back(region_us / paper_us);
  }
  return {median_of(region_round_us), median_of(paper_round_us), median_of(ratios),
          paper.region.cells};
}

}  // namespace

int run_perception_bench(const PerceptionBenchOptions& options) {
  // One thread everywhere: the SSM is one loop on one core, so OpenCV gets one core too.
  cv::setNumThreads(1);
  const int repeats = options.repeats;
  const BenchStereoPair pair = make_bench_pair();
  const SsmConfigs configs = bench_ssm_configs();
  PerceptionBenchFigures figures;
  figures.repeats = repeats;
  figures.rounds = kRounds;
  figures.ssm = time_ssm_variants(configs, pair, repeats);
  // One servo for both alternated comparisons: the second starts warm from the first.
  SsmRun paper_run(configs.paper, pair.left, pair.right);
  const int per_round = std::max(5, repeats / kRounds);
  figures.memcpy_rounds = time_memcpy_rounds(pair, paper_run, per_round);
  figures.scan_rounds = time_scan_rounds(configs.paper, pair, paper_run, per_round);
  // The worst case, side by side with the paper's SSM on the same stripes.
  const BenchStereoPair stripes = make_horizontal_stripes_pair();
  SsmRun paper_on_stripes(configs.paper, stripes.left, stripes.right);
  figures.widest_window_rounds =
      time_scan_rounds(configs.paper, stripes, paper_on_stripes, per_round);
  figures.region_rounds = time_region_rounds(configs.paper, pair, paper_run, per_round);
  figures.opencv_filter_us = time_full_image_filter(configs.paper.operators, pair.left, pair.right,
                                                    std::max(5, repeats / 5));
  figures.stereo_bm_us = time_stereo_bm(pair.left, pair.right, std::max(5, repeats / 5));
  if (options.json) {
    print_perception_bench_json(figures);
  } else {
    print_perception_bench_table(figures);
  }
  return kExitOk;
}

}  // namespace cambio::app
