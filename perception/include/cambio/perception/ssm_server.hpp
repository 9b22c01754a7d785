#pragma once

#include <memory>
#include <string>

#include "cambio/hal/camera.hpp"
#include "cambio/hal/image.hpp"
#include "cambio/hal/loop.hpp"
#include "cambio/hal/seqlock_channel.hpp"
#include "cambio/hal/stereo_frame.hpp"
#include "cambio/hal/triple_buffer.hpp"
#include "cambio/perception/sensory_servo.hpp"

namespace cambio::perception {

/// What the decision layer wants next: where each eye's retina sits and which features.
struct SsmRequest {
  bool fixation_set = false;  ///< False: each retina is centred on its image.
  std::array<PixelPoint, 2> fixation{};
  FeatureRequest features;
};

/// The SSM as an information server (paper Section 4): a perception loop that takes the newest
/// stereo pair the camera loop published, builds the retinas at the requested fixation points,
/// computes the requested features and publishes them on latest-value channels. configure()
/// allocates everything; update() never allocates, locks or blocks.
class SsmServer final : public hal::Loop {
 public:
  /// `pairs`: the camera loop's stereo channel (this loop is its only reader). `left`/`right`:
  /// the two cameras' descriptions (sizes, formats, rate).
  SsmServer(std::string name, hal::TripleBuffer<hal::StereoFrame>& pairs,
            const hal::CameraInfo& left, const hal::CameraInfo& right, SsmConfig config);
  ~SsmServer() override;

  const std::string& name() const override { return name_; }
  /// Builds the pipeline. Throws std::invalid_argument if the cameras differ in size or the
  /// config is inconsistent.
  void configure() override;
  void activate() override;
  /// kNoNewData when no new pair arrived; kRejected when not configured, when a pair's images
  /// do not match the cameras, or when its two stamps differ by more than half a camera period
  /// (counted in mismatched_pairs(); the pair is not used). Real-time safe.
  hal::Status update(const hal::LoopTick& tick) noexcept override;

  /// Pairs refused because their eyes' stamps were more than half a camera period apart.
  std::uint64_t mismatched_pairs() const { return mismatched_pairs_; }
  /// Largest stamp difference accepted within a pair (ns): half the camera period.
  std::int64_t max_stamp_skew_ns() const { return max_stamp_skew_ns_; }

  /// Written by the decision layer (one writer), read here each cycle.
  hal::SeqlockChannel<SsmRequest>& requests() { return requests_; }
  /// The newest summary (disparity, motion, moments). Any number of readers.
  const hal::SeqlockChannel<SsmSummary>& summaries() const { return summaries_; }
  /// The newest full frame with feature maps (one reader). Valid after configure().
  hal::TripleBuffer<SsmFrame>& frames() { return *frames_; }
  /// The pipeline (operators, retina geometry); null before configure().
  const SensoryServo* servo() const { return servo_.get(); }

 private:
  std::string name_;
  hal::TripleBuffer<hal::StereoFrame>& pairs_;
  hal::CameraInfo left_info_;
  hal::CameraInfo right_info_;
  SsmConfig config_;
  std::int64_t max_stamp_skew_ns_ = 0;
  std::uint64_t mismatched_pairs_ = 0;
  SsmRequest request_{};  // The last clean request (a torn read keeps it).
  std::unique_ptr<SensoryServo> servo_;
  std::unique_ptr<hal::TripleBuffer<SsmFrame>> frames_;
  hal::SeqlockChannel<SsmRequest> requests_;
  hal::SeqlockChannel<SsmSummary> summaries_;
};

}  // namespace cambio::perception
