#include "camera_throughput.hpp"

#include <chrono>
#include <cstdint>
#include <memory>
#include <stdexcept>
#include <vector>

#include "bench_timing.hpp"

namespace cambio::app {

namespace {

using Clock = std::chrono::steady_clock;

// Stereo pairs rendered in some seconds of wall time.
struct Round {
  int pairs = 0;
  double seconds = 0.0;
  double fps() const { return seconds > 0.0 ? pairs / seconds : 0.0; }
  Round& operator+=(const Round& other) {
    pairs += other.pairs;
    seconds += other.seconds;
    return *this;
  }
};

// Both eyes of a sim backend grabbed through the HAL, a physics step between pairs so that every
// pair is a new frame; the physics step's time is not counted.
class StereoPipeline {
 public:
  StereoPipeline(sim::SimBackend& backend, const config::RigConfig& rig) : backend_(backend) {
    backend_.activate();
    left_ = backend_.make_camera(rig.stereo->left_camera);
    right_ = backend_.make_camera(rig.stereo->right_camera);
    const auto& k = left_->info().intrinsics;
    left_image_ = hal::Image(k.width_px, k.height_px, left_->info().format);
    right_image_ = hal::Image(k.width_px, k.height_px, right_->info().format);
  }
  const hal::CameraIntrinsics& intrinsics() const { return left_->info().intrinsics; }
  hal::PixelFormat format() const { return left_->info().format; }

  Round round(double budget_s) {
    int pairs = 0;
    const auto start = Clock::now();
    double physics_s = 0.0;
    while (seconds_since(start) < budget_s) {
      const auto physics_start = Clock::now();
      stamp_ns_ += 1'000'000;
      (void)backend_.physics().step_once(stamp_ns_);
      physics_s += seconds_since(physics_start);
      if (left_->grab(left_image_) != hal::Status::kOk ||
          right_->grab(right_image_) != hal::Status::kOk) {
        throw std::runtime_error("a camera grab failed during the benchmark");
      }
      ++pairs;
    }
    return {pairs, seconds_since(start) - physics_s};
  }

 private:
  sim::SimBackend& backend_;
  std::unique_ptr<hal::Camera> left_;
  std::unique_ptr<hal::Camera> right_;
  hal::Image left_image_;
  hal::Image right_image_;
  std::int64_t stamp_ns_ = 0;
};

// The reference: both eyes rendered and read back by MuJoCo alone, holding the renderer for the
// whole round.
class RawReferenceLoop {
 public:
  RawReferenceLoop(sim::SimBackend& backend, const config::RigConfig& rig,
                   const hal::CameraIntrinsics& intrinsics)
      : renderer_(backend.renderer()),
        left_id_(backend.world().camera_id(rig.stereo->left_camera)),
        right_id_(backend.world().camera_id(rig.stereo->right_camera)),
        width_px_(intrinsics.width_px),
        height_px_(intrinsics.height_px),
        raw_(static_cast<std::size_t>(intrinsics.width_px) * intrinsics.height_px * 3) {}

  Round round(double budget_s) {
    int pairs = 0;
    const auto start = Clock::now();
    const sim::Renderer::Lease lease(renderer_, sim::Renderer::Lease::Mode::kWait);
    while (seconds_since(start) < budget_s) {
      renderer_.render_raw_reference(left_id_, width_px_, height_px_, raw_.data());
      renderer_.render_raw_reference(right_id_, width_px_, height_px_, raw_.data());
      ++pairs;
    }
    return Round{pairs, seconds_since(start)};
  }

 private:
  sim::Renderer& renderer_;
  int left_id_;
  int right_id_;
  int width_px_;
  int height_px_;
  std::vector<std::uint8_t> raw_;
};

}  // namespace

CameraFigures measure_cameras(sim::SimBackend& whole_backend, sim::SimBackend* foveated_backend,
                              const config::RigConfig& rig, double seconds) {
  StereoPipeline whole(whole_backend, rig);
  std::optional<StereoPipeline> foveated;
  if (foveated_backend) foveated.emplace(*foveated_backend, rig);
  const auto& intrinsics = whole.intrinsics();
  RawReferenceLoop raw(whole_backend, rig, intrinsics);
  (void)whole.round(0.2);  // Warm-up: JIT-compiled llvmpipe shaders, caches.
  if (foveated) (void)foveated->round(0.2);
  (void)raw.round(0.2);
  // Short alternating rounds; each ratio is the median of the rounds' ratios, so a burst of
  // load from another process skews one round, not the figure.
  constexpr int kRounds = 10;
  Round whole_total, foveated_total, raw_total;
  std::vector<double> whole_ratios, foveated_ratios;
  for (int round = 0; round < kRounds; ++round) {
    const Round w = whole.round(seconds / kRounds);
    const Round f = foveated ? foveated->round(seconds / kRounds) : Round{};
    const Round r = raw.round(seconds / kRounds);
    whole_total += w;
    foveated_total += f;
    raw_total += r;
    whole_ratios.push_back(w.fps() / r.fps());
    if (foveated) foveated_ratios.push_back(f.fps() / r.fps());
  }
  CameraFigures figures;
  figures.width_px = intrinsics.width_px;
  figures.height_px = intrinsics.height_px;
  figures.format = whole.format();
  figures.camera_fps = whole_total.fps();
  figures.raw_fps = raw_total.fps();
  figures.camera_vs_raw = median_of(whole_ratios);
  if (foveated) {
    figures.foveated_fps = foveated_total.fps();
    figures.foveated_vs_raw = median_of(foveated_ratios);
  }
  figures.rounds = kRounds;
  return figures;
}

}  // namespace cambio::app
