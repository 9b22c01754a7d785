#include "cambio/perception/sensory_servo.hpp"

#include <algorithm>
#include <chrono>
#include <stdexcept>

namespace cambio::perception {

namespace {

using SteadyClock = std::chrono::steady_clock;

double microseconds_since(SteadyClock::time_point start, SteadyClock::time_point end) {
  return std::chrono::duration<double, std::micro>(end - start).count();
}

}  // namespace

SensoryServo::SensoryServo(const SsmConfig& config, int image_width_px, int image_height_px)
    : config_(config),
      image_width_(image_width_px),
      image_height_(image_height_px),
      bank_(config.operators, config.retina.width_px, config.retina.height_px),
      disparity_(config.disparity, bank_, config.retina.width_px, config.retina.height_px),
      region_(config.region) {
  if (image_width_px <= 0 || image_height_px <= 0) {
    throw std::invalid_argument("the SSM needs a positive image size");
  }
  int apron = bank_.apron_px();
  for (std::size_t eye = 0; eye < 2; ++eye) {
    motion_[eye] = std::make_unique<MotionEstimator>(
        config.motion, config.operators.half_width_sigmas, config.retina.levels,
        config.retina.width_px, config.retina.height_px);
    apron = std::max(apron, motion_[eye]->apron_px());
  }
  for (auto& retina : retinas_) {
    retina = std::make_unique<Retina>(config.retina, apron, image_width_px, image_height_px);
  }
  shifted_right_ = std::make_unique<ShiftedRight>(
      *this, std::make_unique<Retina>(config.retina, apron, image_width_px, image_height_px),
      FeatureMaps(config.retina.levels, bank_.map_count(), config.retina.width_px,
                  config.retina.height_px));
  scan_ = std::make_unique<DisparityScan>(config.disparity, config.operators, bank_, config.retina,
                                          image_width_px, image_height_px);
  moments_map_ = bank_.find(config.moments.map);
  if (moments_map_ < 0) {
    throw std::invalid_argument("moments map '" + config.moments.map + "' is not a feature map");
  }
}

SensoryServo::~SensoryServo() = default;

void SensoryServo::set_lenses(const LensDistortion& left, const LensDistortion& right) {
  // One table of corners per eye, shared by every retina that reads that eye.
  const auto map = [&](const LensDistortion& lens) -> std::shared_ptr<const LensCornerMap> {
    if (lens.is_identity()) return nullptr;
    return std::make_shared<const LensCornerMap>(lens, image_width_, image_height_);
  };
  const std::shared_ptr<const LensCornerMap> left_map = map(left);
  const std::shared_ptr<const LensCornerMap> right_map = map(right);
  retinas_[0]->set_lens(left_map);
  retinas_[1]->set_lens(right_map);
  shifted_right_->set_lens(right_map);
  scan_->set_lenses(left_map, right_map);
}

const float* SensoryServo::ShiftedRight::shifted_right_level(int k, int offset_px) noexcept {
  if (image_ == nullptr) return nullptr;
  const Retina& right = *servo_.retinas_[1];
  const int scale = right.level(k).scale_px;
  const PixelPoint moved{fixation_.x - offset_px * scale, fixation_.y};
  // A field-covering level changes its block size with the fixation; its samples would no
  // longer line up with the left level's.
  if (retina_->build_one_level(*image_, k, moved) != hal::Status::kOk ||
      retina_->level(k).scale_px != scale) {
    return nullptr;
  }
  servo_.bank_.apply(retina_->level(k), servo_.disparity_.required_maps(), maps_.level(k));
  return maps_.level(k);
}

SsmFrame SensoryServo::make_frame() const {
  SsmFrame frame;
  for (auto& maps : frame.maps) {
    maps = FeatureMaps(config_.retina.levels, bank_.map_count(), config_.retina.width_px,
                       config_.retina.height_px);
  }
  for (auto& temporal : frame.temporal) {
    temporal.assign(static_cast<std::size_t>(config_.retina.levels) * config_.retina.width_px *
                        config_.retina.height_px,
                    0.0f);
  }
  return frame;
}

void SensoryServo::reset_motion() noexcept {
  for (auto& motion : motion_) motion->reset();
}

hal::Status SensoryServo::process(const hal::Image& left, const hal::Image& right,
                                  PixelPoint left_fixation, PixelPoint right_fixation,
                                  const FeatureRequest& request, SsmFrame& out) noexcept {
  const auto right_size = [this](const hal::Image& image) {
    return !image.empty() && image.width_px == image_width_ && image.height_px == image_height_;
  };
  if (!right_size(left) || !right_size(right)) return hal::Status::kRejected;
  if (out.maps[0].levels() != config_.retina.levels || out.maps[0].maps() != bank_.map_count()) {
    return hal::Status::kRejected;
  }
  const auto start = SteadyClock::now();
  SsmSummary& summary = out.summary;
  summary.sequence = ++sequence_;
  summary.stamp_ns = left.stamp_ns;
  summary.levels = config_.retina.levels;
  summary.fixation = {left_fixation, right_fixation};
  const std::array<const hal::Image*, 2> images{&left, &right};
  for (std::size_t eye = 0; eye < 2; ++eye) {
    if (retinas_[eye]->build(*images[eye], summary.fixation[eye]) != hal::Status::kOk) {
      return hal::Status::kRejected;
    }
    for (int k = 0; k < config_.retina.levels; ++k) {
      const RetinaLevelView level = retinas_[eye]->level(k);
      summary.geometry[eye][static_cast<std::size_t>(k)] = {
          level.scale_px, level.origin_x_px, level.origin_y_px, level.fraction_inside};
    }
  }
  const auto retinas_done = SteadyClock::now();

  MapMask maps = request.maps;
  if (request.disparity && config_.disparity.enabled) maps |= disparity_.required_maps();
  if (request.moments && config_.moments.enabled) maps |= MapMask{1} << moments_map_;
  if (bank_.map_count() < kMaxMaps) maps &= (MapMask{1} << bank_.map_count()) - 1;
  for (std::size_t eye = 0; eye < 2; ++eye) {
    for (int k = 0; k < config_.retina.levels; ++k) {
      bank_.apply(retinas_[eye]->level(k), maps, out.maps[eye].level(k));
    }
    out.maps[eye].set_computed(maps);
  }
  const auto features_done = SteadyClock::now();

  summary.disparity = DisparityResult{};
  if (request.disparity && config_.disparity.enabled) {
    shifted_right_->prepare(right, right_fixation);
    const bool scanned = scan_->enabled();
    if (scanned) {
      scan_->scan(out.maps[0], left, left_fixation, right, right_fixation, scan_result_);
    }
    disparity_.estimate(out.maps[0], out.maps[1], *retinas_[0], *retinas_[1], summary.disparity,
                        shifted_right_.get(), scanned ? &scan_result_ : nullptr);
  }
  const auto disparity_done = SteadyClock::now();

  for (std::size_t eye = 0; eye < 2; ++eye) {
    summary.motion[eye] = MotionResult{};
    if (request.motion && config_.motion.enabled) {
      const bool sized =
          out.temporal[eye].size() == static_cast<std::size_t>(config_.retina.levels) *
                                          config_.retina.width_px * config_.retina.height_px;
      motion_[eye]->estimate(*retinas_[eye], summary.motion[eye],
                             sized ? out.temporal[eye].data() : nullptr);
    } else {
      // The next requested estimate must not compare against a frame from before the gap.
      motion_[eye]->reset();
    }
  }
  const auto motion_done = SteadyClock::now();

  for (std::size_t eye = 0; eye < 2; ++eye) {
    for (int k = 0; k < config_.retina.levels; ++k) {
      Moments& moments = summary.moments[eye][static_cast<std::size_t>(k)];
      moments = Moments{};
      if (!request.moments || !config_.moments.enabled) continue;
      moments =
          compute_moments(out.maps[eye].map(k, moments_map_), config_.retina.width_px,
                          retinas_[eye]->level(k), config_.moments.mode, config_.moments.threshold);
    }
  }
  const auto moments_done = SteadyClock::now();

  summary.region = FixatedRegion{};
  if (request.region && config_.region.enabled) {
    region_.find(left, left_fixation, right, right_fixation, summary.region);
  }
  const auto end = SteadyClock::now();
  summary.timings = {microseconds_since(start, retinas_done),
                     microseconds_since(retinas_done, features_done),
                     microseconds_since(features_done, disparity_done),
                     microseconds_since(disparity_done, motion_done),
                     microseconds_since(motion_done, moments_done),
                     microseconds_since(start, end),
                     microseconds_since(moments_done, end)};
  return hal::Status::kOk;
}

}  // namespace cambio::perception
