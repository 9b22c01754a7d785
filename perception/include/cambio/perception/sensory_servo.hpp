#pragma once

#include <array>
#include <cstdint>
#include <memory>
#include <vector>

#include "cambio/hal/eye.hpp"
#include "cambio/hal/image.hpp"
#include "cambio/hal/status.hpp"
#include "cambio/perception/disparity_estimator.hpp"
#include "cambio/perception/feature_maps.hpp"
#include "cambio/perception/fixated_region.hpp"
#include "cambio/perception/moments.hpp"
#include "cambio/perception/motion_estimator.hpp"
#include "cambio/perception/operator_bank.hpp"
#include "cambio/perception/perception_config.hpp"
#include "cambio/perception/retina.hpp"

namespace cambio::perception {

/// What the decision layer asks the SSM for (paper Section 4: "building feature maps as needed").
struct FeatureRequest {
  MapMask maps = kAllMaps;  ///< Bit i: map i of the operator set.
  bool disparity = true;
  bool motion = true;
  bool moments = true;
  /// The fixated object's region (ZeroDisparityFilter): off unless asked for, it reads the
  /// source images around the fixation rather than the retina.
  bool region = false;
};

/// Where a level's samples lie in the source image.
struct LevelGeometry {
  int scale_px = 1;
  int origin_x_px = 0;
  int origin_y_px = 0;
  float fraction_inside = 1.0f;
};

struct SsmTimings {
  double retina_us = 0.0;
  double features_us = 0.0;
  double disparity_us = 0.0;
  double motion_us = 0.0;
  double moments_us = 0.0;
  double total_us = 0.0;
  double region_us = 0.0;  ///< Part of total_us; 0 when the region was not asked for.
};

/// The small, trivially copyable part of a result (fits a SeqlockChannel).
struct SsmSummary {
  std::uint64_t sequence = 0;  ///< Frames processed so far; 0 = none yet.
  std::int64_t stamp_ns = 0;   ///< The left image's exposure stamp.
  int levels = 0;
  std::array<PixelPoint, 2> fixation{};
  std::array<std::array<LevelGeometry, Retina::kMaxLevels>, 2> geometry{};
  DisparityResult disparity;
  std::array<MotionResult, 2> motion{};
  std::array<std::array<Moments, Retina::kMaxLevels>, 2> moments{};
  FixatedRegion region;
  SsmTimings timings;
};

/// A whole result: the summary plus every feature map of both eyes (fits a TripleBuffer).
struct SsmFrame {
  SsmSummary summary;
  std::array<FeatureMaps, 2> maps;
  /// Per eye, levels x width x height: the temporal derivative of the smoothed retina (current
  /// minus previous frame; zero on the first frame).
  std::array<std::vector<float>, 2> temporal;
};

/// The Sensory Servo Module's per-frame pipeline (paper Section 4): for each eye a retina at its
/// fixation point, the requested operators on every level, then disparity between the eyes,
/// motion against the previous frame, moments, and when asked the fixated object's region.
/// Everything is allocated by the constructor;
/// process() never allocates. Not thread-safe.
class SensoryServo {
 public:
  /// Throws std::invalid_argument for an inconsistent config.
  SensoryServo(const SsmConfig& config, int image_width_px, int image_height_px);
  ~SensoryServo();
  SensoryServo(const SensoryServo&) = delete;
  SensoryServo& operator=(const SensoryServo&) = delete;

  /// A frame with every buffer sized for this pipeline (allocates; call at configure).
  SsmFrame make_frame() const;

  /// Processes one stereo pair. kRejected when an image is empty or not the configured size.
  /// Real-time safe (no allocation, no locks).
  hal::Status process(const hal::Image& left, const hal::Image& right, PixelPoint left_fixation,
                      PixelPoint right_fixation, const FeatureRequest& request,
                      SsmFrame& out) noexcept;

  /// Forgets the previous frame used for motion.
  void reset_motion() noexcept;

  const SsmConfig& config() const { return config_; }
  const OperatorBank& operators() const { return bank_; }
  const Retina& retina(hal::Eye eye) const { return *retinas_[static_cast<std::size_t>(eye)]; }
  int moments_map() const { return moments_map_; }
  int image_width_px() const { return image_width_; }
  int image_height_px() const { return image_height_; }
  /// The cameras' lenses (configure time: allocates): from now on every retina samples the
  /// ideal (pinhole) image of its eye's camera, read from the distorted one (Retina::set_lens),
  /// so the disparity, the motion and the servo that uses them see undistorted geometry.
  void set_lenses(const LensDistortion& left, const LensDistortion& right);
  /// The last whole-range scan's hypotheses (searched false when the scan is off or failed).
  const DisparityScanResult& last_scan() const { return scan_result_; }

 private:
  SsmConfig config_;
  int image_width_ = 0;
  int image_height_ = 0;
  OperatorBank bank_;
  DisparityEstimator disparity_;
  std::array<std::unique_ptr<Retina>, 2> retinas_;
  std::array<std::unique_ptr<MotionEstimator>, 2> motion_;
  /// Right levels rebuilt around a coarser disparity estimate (DisparityEstimator's
  /// ShiftedLevelSource), into a scratch retina and maps so the frame's right maps stay as seen.
  class ShiftedRight final : public ShiftedLevelSource {
   public:
    ShiftedRight(const SensoryServo& servo, std::unique_ptr<Retina> retina, FeatureMaps maps)
        : servo_(servo), retina_(std::move(retina)), maps_(std::move(maps)) {}
    void prepare(const hal::Image& image, PixelPoint fixation) noexcept {
      image_ = &image;
      fixation_ = fixation;
    }
    const float* shifted_right_level(int k, int offset_px) noexcept override;
    /// The window moves to a few places a frame (one per shift range the search reaches).
    void set_lens(std::shared_ptr<const LensCornerMap> lens) {
      retina_->set_lens(std::move(lens), kPlacesPlanned);
    }
    static constexpr int kPlacesPlanned = 4;

   private:
    const SensoryServo& servo_;
    std::unique_ptr<Retina> retina_;
    FeatureMaps maps_;
    const hal::Image* image_ = nullptr;
    PixelPoint fixation_;
  };

  int moments_map_ = 0;
  std::uint64_t sequence_ = 0;
  std::unique_ptr<ShiftedRight> shifted_right_;
  std::unique_ptr<DisparityScan> scan_;  ///< Off unless disparity.scan_range_px > 0.
  ZeroDisparityFilter region_;
  DisparityScanResult scan_result_;
};

}  // namespace cambio::perception
