// `cambio perception-bench`: the paper's claim, measured. On one 640x480 stereo pair: the whole
// SSM (retinas, every operator at 3 sigmas, disparity, motion, moments) for the paper's 4 x 16 x 16
// retina (its coarsest level covering the whole field) on grey and on rgb8 frames, for the same
// retina without the field-covering level (fovea only) and for 4 x 64 x 64; a memcpy of both
// images (the memory bound), alternated with the paper's SSM in rounds; the same operator set on
// the full images with cv::sepFilter2D (the "filter everything" approach); and cv::StereoBM on
// the full pair. Every figure is the median time per stereo pair.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <functional>
#include <iostream>
#include <numbers>
#include <optional>

#include <unistd.h>

#include <opencv2/calib3d.hpp>
#include <opencv2/core.hpp>
#include <opencv2/imgproc.hpp>
#include <random>
#include <span>
#include <string>
#include <vector>

#include "argument_parser.hpp"
#include "cambio/perception/gaussian_kernels.hpp"
#include "cambio/perception/sensory_servo.hpp"
#include "command.hpp"
#include "json_output.hpp"

namespace cambio::app {

namespace {

using Clock = std::chrono::steady_clock;

constexpr int kWidth = 640;
constexpr int kHeight = 480;

/// A textured pair with 3.3 px of disparity (band-limited, so sub-pixel shifts are exact).
void make_pair(hal::Image& left, hal::Image& right, hal::Image& left_rgb, hal::Image& right_rgb) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  struct Wave {
    double fx, fy, phase, amplitude;
  };
  std::vector<Wave> waves;
  for (int i = 0; i < 48; ++i) {
    const double f =
        std::exp(std::log(1.0 / 256) + (std::log(1.0 / 5) - std::log(1.0 / 256)) * unit(rng));
    const double angle = 2 * std::numbers::pi * unit(rng);
    waves.push_back({f * std::cos(angle), f * std::sin(angle), 2 * std::numbers::pi * unit(rng),
                     3.0 / std::sqrt(f) / 48.0 * 8.0});
  }
  const auto value = [&](double x, double y) {
    double v = 128;
    for (const auto& w : waves)
      v += w.amplitude * std::cos(2 * std::numbers::pi * (w.fx * x + w.fy * y) + w.phase);
    return static_cast<std::uint8_t>(std::clamp(std::lround(v), 0L, 255L));
  };
  left.resize(kWidth, kHeight, hal::PixelFormat::kGrey8);
  right.resize(kWidth, kHeight, hal::PixelFormat::kGrey8);
  for (int y = 0; y < kHeight; ++y) {
    for (int x = 0; x < kWidth; ++x) {
      left.row(y)[x] = value(x, y);
      right.row(y)[x] = value(x + 3.3, y);
    }
  }
  // The same pair as the cameras deliver it: rgb8 whose luma is the grey pair.
  const auto to_rgb = [](const hal::Image& grey, hal::Image& rgb) {
    rgb.resize(grey.width_px, grey.height_px, hal::PixelFormat::kRgb8);
    for (std::size_t i = 0; i < grey.pixels.size(); ++i) {
      for (std::size_t c = 0; c < 3; ++c) rgb.pixels[3 * i + c] = grey.pixels[i];
    }
  };
  to_rgb(left, left_rgb);
  to_rgb(right, right_rgb);
}

/// Median wall time of `run` in microseconds, after a warm-up, over `repeats` runs.
/// The median of `repeats` timed runs, after a few untimed ones; `before` runs untimed before each.
double median_us(
    int repeats, const std::function<void()>& run, const std::function<void()>& before = [] {}) {
  for (int i = 0; i < std::max(3, repeats / 10); ++i) run();
  std::vector<double> samples;
  samples.reserve(static_cast<std::size_t>(repeats));
  for (int i = 0; i < repeats; ++i) {
    before();
    const auto start = Clock::now();
    run();
    samples.push_back(std::chrono::duration<double, std::micro>(Clock::now() - start).count());
  }
  std::nth_element(samples.begin(), samples.begin() + repeats / 2, samples.end());
  return samples[static_cast<std::size_t>(repeats / 2)];
}

struct SsmFigures {
  double total_us = 0;
  perception::SsmTimings parts;
  float disparity_px = 0;
  float confidence = 0;
};

/// One SSM and its output frame, processing the pair fixated at the image centre.
class SsmRun {
 public:
  SsmRun(const perception::SsmConfig& config, const hal::Image& left, const hal::Image& right)
      : servo_(config, kWidth, kHeight), frame_(servo_.make_frame()), left_(left), right_(right) {}
  const perception::SsmFrame& run() {
    const perception::PixelPoint centre{kWidth / 2, kHeight / 2};
    if (servo_.process(left_, right_, centre, centre, perception::FeatureRequest{}, frame_) !=
        hal::Status::kOk) {
      throw std::runtime_error("SSM rejected the benchmark pair");
    }
    return frame_;
  }
  const perception::SsmFrame& frame() const { return frame_; }

 private:
  perception::SensoryServo servo_;
  perception::SsmFrame frame_;
  const hal::Image& left_;
  const hal::Image& right_;
};

/// Pushes the frames out of every cache level: in the robot's loop a stereo pair arrives fresh
/// from the cameras, rendered or DMA'd, not warm from the previous run over the same pair. Writes
/// twice the last-level cache (64 MiB where the size is unknown).
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

enum class Frames : std::uint8_t { kWarm, kFresh };

/// The SSM's median over `repeats` runs on the pair; with Frames::kFresh the caches are evicted
/// before each run (outside the timed span).
SsmFigures time_ssm(const perception::SsmConfig& config, const hal::Image& left,
                    const hal::Image& right, int repeats, Frames frames = Frames::kWarm) {
  SsmRun ssm(config, left, right);
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
  const auto median_of = [&](double perception::SsmTimings::*field) {
    std::vector<double> values;
    for (const auto& p : parts) values.push_back(p.*field);
    std::nth_element(values.begin(),
                     values.begin() + static_cast<std::ptrdiff_t>(values.size() / 2), values.end());
    return values[values.size() / 2];
  };
  figures.parts = {median_of(&perception::SsmTimings::retina_us),
                   median_of(&perception::SsmTimings::features_us),
                   median_of(&perception::SsmTimings::disparity_us),
                   median_of(&perception::SsmTimings::motion_us),
                   median_of(&perception::SsmTimings::moments_us),
                   median_of(&perception::SsmTimings::total_us)};
  figures.disparity_px = ssm.frame().summary.disparity.disparity_px;
  figures.confidence = ssm.frame().summary.disparity.confidence;
  return figures;
}

/// The SSM's operator set on a whole image with OpenCV: per sigma the six Eq. 3-5 maps by
/// cv::sepFilter2D plus their sum (LoG), Sobel x and y, and the 3x3 box, on a float copy.
class FullImageFilter {
 public:
  explicit FullImageFilter(const perception::OperatorConfig& ops) {
    for (const double sigma : ops.sigmas_px) {
      const int s = perception::gaussian_half_width(sigma, ops.half_width_sigmas);
      Family family;
      family.order0 =
          as_mat(perception::gaussian_derivative_kernel(0, perception::Axis::kX, sigma, s).row);
      const auto first = perception::gaussian_derivative_kernel(1, perception::Axis::kX, sigma, s);
      family.order1 = as_mat(first.row);
      family.across = as_mat(first.column);
      family.order2 =
          as_mat(perception::gaussian_derivative_kernel(2, perception::Axis::kX, sigma, s).row);
      families_.push_back(family);
    }
  }
  void run(const hal::Image& image) {
    const cv::Mat grey(image.height_px, image.width_px, CV_8U,
                       const_cast<std::uint8_t*>(image.pixels.data()));
    grey.convertTo(source_, CV_32F);
    const cv::Mat one = cv::Mat::ones(1, 1, CV_32F);
    for (const auto& f : families_) {
      // filter2D-family functions correlate; the masks are flipped to convolve (Eq. 2).
      cv::sepFilter2D(source_, out_[0], CV_32F, flip(f.order0), one);
      cv::sepFilter2D(source_, out_[1], CV_32F, one, flip(f.order0));
      cv::sepFilter2D(source_, out_[2], CV_32F, flip(f.order1), f.across);
      cv::sepFilter2D(source_, out_[3], CV_32F, f.across, flip(f.order1));
      cv::sepFilter2D(source_, out_[4], CV_32F, f.order2, f.across);
      cv::sepFilter2D(source_, out_[5], CV_32F, f.across, f.order2);
      cv::add(out_[4], out_[5], out_[6]);
    }
    cv::Sobel(source_, out_[7], CV_32F, 1, 0, 3);
    cv::Sobel(source_, out_[8], CV_32F, 0, 1, 3);
    cv::blur(source_, out_[9], cv::Size(3, 3));
  }

 private:
  struct Family {
    cv::Mat order0, order1, order2, across;
  };
  static cv::Mat as_mat(const std::vector<double>& taps) {
    cv::Mat mat(static_cast<int>(taps.size()), 1, CV_32F);
    for (std::size_t i = 0; i < taps.size(); ++i)
      mat.at<float>(static_cast<int>(i)) = static_cast<float>(taps[i]);
    return mat;
  }
  static cv::Mat flip(const cv::Mat& taps) {
    cv::Mat flipped;
    cv::flip(taps, flipped, 0);
    return flipped;
  }
  std::vector<Family> families_;
  cv::Mat source_;
  std::array<cv::Mat, 10> out_;
};

}  // namespace

int run_perception_bench_command(std::span<const std::string> args) {
  ArgumentParser parser("perception-bench", "[--json] [--repeats N]");
  parser.flag("json", "print one JSON object with the medians and ratios")
      .option("repeats", "N",
              "timed runs per figure, 5 to 100000 (default 300; the 64x64 SSM and OpenCV use N/5, "
              "each memcpy-vs-SSM round N/11)");
  if (!parser.parse(args)) return kExitOk;
  const int repeats = static_cast<int>(parser.integer(
      "repeats", 300, config::Range::closed(5, 100'000),
      "a median needs at least 5 runs; at 100000 a run already takes about an hour"));
  // One thread everywhere: the SSM is one loop on one core, so OpenCV gets one core too.
  cv::setNumThreads(1);

  hal::Image left;
  hal::Image right;
  hal::Image left_rgb;
  hal::Image right_rgb;
  make_pair(left, right, left_rgb, right_rgb);

  // The paper's retina: 4 x 16 x 16, its coarsest level widened to cover the whole field;
  // sigmas 1.4, 2.7, 4, s = ceil(3 sigma).
  perception::SsmConfig paper;
  paper.retina.coarsest_covers_field = true;
  perception::SsmConfig fovea_only = paper;  // Coarsest level 8 px blocks, 128 px wide.
  fovea_only.retina.coarsest_covers_field = false;
  perception::SsmConfig wide = fovea_only;
  wide.retina.width_px = 64;
  wide.retina.height_px = 64;
  const SsmFigures ssm_paper = time_ssm(paper, left, right, repeats);
  const SsmFigures ssm_paper_rgb = time_ssm(paper, left_rgb, right_rgb, repeats);
  const SsmFigures ssm_fovea_only = time_ssm(fovea_only, left, right, repeats);
  // Eviction takes milliseconds a run: fewer repeats.
  const int fresh_repeats = std::max(5, repeats / 5);
  const SsmFigures ssm_paper_fresh = time_ssm(paper, left, right, fresh_repeats, Frames::kFresh);
  const SsmFigures ssm_paper_rgb_fresh =
      time_ssm(paper, left_rgb, right_rgb, fresh_repeats, Frames::kFresh);
  const SsmFigures ssm_64 = time_ssm(wide, left, right, std::max(5, repeats / 5));

  // The memory bound, alternated with the paper's SSM in short rounds: the ratio is the median
  // of the rounds' ratios, so a burst of load from another process skews one round, not the
  // figure (as sim-bench does for rendering).
  hal::Image left_copy = left;
  hal::Image right_copy = right;
  const auto copy_both = [&] {
    std::memcpy(left_copy.pixels.data(), left.pixels.data(), left.pixels.size());
    std::memcpy(right_copy.pixels.data(), right.pixels.data(), right.pixels.size());
    asm volatile("" : : "r"(left_copy.pixels.data()), "r"(right_copy.pixels.data()) : "memory");
  };
  SsmRun paper_run(paper, left, right);
  constexpr int kRounds = 11;
  const int per_round = std::max(5, repeats / kRounds);
  std::vector<double> memcpy_round_us;
  std::vector<double> ratios;
  for (int round = 0; round < kRounds; ++round) {
    const double copy_us = median_us(per_round, copy_both);
    const double ssm_us = median_us(per_round, [&] { (void)paper_run.run(); });
    memcpy_round_us.push_back(copy_us);
    ratios.push_back(ssm_us / copy_us);
  }
  const auto median = [](std::vector<double> values) {
    std::sort(values.begin(), values.end());
    return values[values.size() / 2];
  };
  const double memcpy_us = median(memcpy_round_us);

  // The paper's SSM with the whole-range disparity scan, as a run on the shipped head uses it
  // (the range f b / 0.3 m), alternated round by round with the paper's SSM without it.
  constexpr double kShippedHeadFocal_px = 554.256;
  constexpr double kShippedHeadBaseline_m = 0.12;
  perception::SsmConfig paper_scan = paper;
  paper_scan.disparity.scan_range_px =
      perception::largest_disparity_px(kShippedHeadFocal_px, kShippedHeadBaseline_m);
  SsmRun scan_run(paper_scan, left, right);
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
  const double scan_disparity_us = scan_run.frame().summary.timings.disparity_us;
  const double paper_vs_memcpy = median(ratios);

  FullImageFilter full(paper.operators);
  const double opencv_filter_us = median_us(std::max(5, repeats / 5), [&] {
    full.run(left);
    full.run(right);
  });

  const cv::Mat left_mat(kHeight, kWidth, CV_8U, left.pixels.data());
  const cv::Mat right_mat(kHeight, kWidth, CV_8U, right.pixels.data());
  cv::Ptr<cv::StereoBM> matcher = cv::StereoBM::create(64, 15);
  cv::Mat disparity;
  const double stereo_bm_us = median_us(std::max(5, repeats / 5),
                                        [&] { matcher->compute(left_mat, right_mat, disparity); });

  const double paper_vs_filter = opencv_filter_us / ssm_paper.total_us;
  const double wide_vs_filter = opencv_filter_us / ssm_64.total_us;
  const double wide_vs_memcpy = ssm_64.total_us / memcpy_us;
  if (parser.flag_set("json")) {
    const auto parts = [](const perception::SsmTimings& t) {
      return Json{{"retina", as_printed(t.retina_us, "%.2f")},
                  {"features", as_printed(t.features_us, "%.2f")},
                  {"disparity", as_printed(t.disparity_us, "%.2f")},
                  {"motion", as_printed(t.motion_us, "%.2f")},
                  {"moments", as_printed(t.moments_us, "%.2f")}};
    };
    const Json figures = {
        {"image", "640x480 stereo pair, grey8 (and rgb8 for ssm_paper_rgb)"},
        {"threads", 1},
        {"repeats", repeats},
        {"ssm_paper_us", as_printed(ssm_paper.total_us, "%.2f")},
        {"ssm_paper_rgb_us", as_printed(ssm_paper_rgb.total_us, "%.2f")},
        {"ssm_fovea_only_us", as_printed(ssm_fovea_only.total_us, "%.2f")},
        {"ssm_paper_fresh_us", as_printed(ssm_paper_fresh.total_us, "%.2f")},
        {"ssm_paper_rgb_fresh_us", as_printed(ssm_paper_rgb_fresh.total_us, "%.2f")},
        {"ssm_64_us", as_printed(ssm_64.total_us, "%.2f")},
        {"memcpy_us", as_printed(memcpy_us, "%.2f")},
        {"opencv_full_filter_us", as_printed(opencv_filter_us, "%.1f")},
        {"opencv_stereo_bm_us", as_printed(stereo_bm_us, "%.1f")},
        {"opencv_full_filter_over_ssm_paper", as_printed(paper_vs_filter, "%.1f")},
        {"ssm_paper_over_memcpy", as_printed(paper_vs_memcpy, "%.2f")},
        {"ssm_paper_over_memcpy_rounds", kRounds},
        {"ssm_paper_rgb_over_ssm_paper",
         as_printed(ssm_paper_rgb.total_us / ssm_paper.total_us, "%.2f")},
        {"ssm_paper_retina_over_fovea_only_retina",
         as_printed(ssm_paper.parts.retina_us / ssm_fovea_only.parts.retina_us, "%.2f")},
        {"ssm_paper_rgb_retina_over_ssm_paper_retina",
         as_printed(ssm_paper_rgb.parts.retina_us / ssm_paper.parts.retina_us, "%.2f")},
        {"opencv_full_filter_over_ssm_64", as_printed(wide_vs_filter, "%.1f")},
        {"ssm_64_over_memcpy", as_printed(wide_vs_memcpy, "%.2f")},
        {"opencv_stereo_bm_over_ssm_paper", as_printed(stereo_bm_us / ssm_paper.total_us, "%.1f")},
        {"ssm_paper_parts_us", parts(ssm_paper.parts)},
        {"ssm_paper_rgb_parts_us", parts(ssm_paper_rgb.parts)},
        {"ssm_paper_fresh_parts_us", parts(ssm_paper_fresh.parts)},
        {"ssm_paper_rgb_fresh_parts_us", parts(ssm_paper_rgb_fresh.parts)},
        {"ssm_fovea_only_parts_us", parts(ssm_fovea_only.parts)},
        {"ssm_64_parts_us", parts(ssm_64.parts)},
        {"ssm_paper_disparity_px", as_printed(ssm_paper.disparity_px, "%.3f")},
        {"ssm_fovea_only_disparity_px", as_printed(ssm_fovea_only.disparity_px, "%.3f")},
        {"ssm_64_disparity_px", as_printed(ssm_64.disparity_px, "%.3f")},
        {"ssm_paper_scan_us", as_printed(median(scan_round_us), "%.2f")},
        {"ssm_paper_in_scan_rounds_us", as_printed(median(paper_round_us), "%.2f")},
        {"ssm_paper_scan_over_ssm_paper", as_printed(median(scan_ratios), "%.2f")},
        {"ssm_paper_scan_disparity_part_us", as_printed(scan_disparity_us, "%.2f")},
        {"ssm_paper_scan_range_px", as_printed(paper_scan.disparity.scan_range_px, "%.1f")},
        {"ssm_paper_scan_disparity_px",
         as_printed(scan_run.frame().summary.disparity.disparity_px, "%.3f")},
        {"true_disparity_px", 3.3}};
    std::cout << json_text(figures);
    return kExitOk;
  }
  std::printf("perception-bench: 640x480 stereo pair, one thread, medians per pair\n");
  const auto print_ssm = [](const char* name, const SsmFigures& f) {
    std::printf(
        "  %-28s%10.1f us   (retina %.1f, features %.1f, disparity %.1f, motion %.1f, "
        "moments %.1f)\n",
        name, f.total_us, f.parts.retina_us, f.parts.features_us, f.parts.disparity_us,
        f.parts.motion_us, f.parts.moments_us);
  };
  print_ssm("SSM paper (grey)", ssm_paper);
  print_ssm("SSM paper (rgb8)", ssm_paper_rgb);
  print_ssm("SSM fovea only (grey)", ssm_fovea_only);
  print_ssm("SSM paper, fresh frames", ssm_paper_fresh);
  print_ssm("SSM paper (rgb8), fresh", ssm_paper_rgb_fresh);
  print_ssm("SSM 4 x 64 x 64 (fovea)", ssm_64);
  std::printf(
      "  SSM paper + disparity scan  %10.1f us   (+-%.0f px; %.2fx the paper SSM, median of %d "
      "alternating rounds)\n",
      median(scan_round_us), paper_scan.disparity.scan_range_px, median(scan_ratios), kRounds);
  std::printf("  memcpy of both images       %10.1f us   (median of %d rounds)\n", memcpy_us,
              kRounds);
  std::printf("  OpenCV full-image filters   %10.1f us   (same operator set, cv::sepFilter2D)\n",
              opencv_filter_us);
  std::printf("  OpenCV StereoBM full pair   %10.1f us\n", stereo_bm_us);
  std::printf(
      "  paper SSM: %.0fx faster than full-image filtering, %.2fx a memcpy (median of %d "
      "alternating rounds)\n",
      paper_vs_filter, paper_vs_memcpy, kRounds);
  std::printf("  64x64 SSM: %.0fx faster than full-image filtering, %.2fx a memcpy\n",
              wide_vs_filter, wide_vs_memcpy);
  std::printf("  disparity at the fovea: %.3f px (paper), %.3f px (64x64); true 3.3 px\n",
              static_cast<double>(ssm_paper.disparity_px),
              static_cast<double>(ssm_64.disparity_px));
  return kExitOk;
}

}  // namespace cambio::app
