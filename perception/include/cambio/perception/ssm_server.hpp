#pragma once

#include <memory>
#include <string>

#include "cambio/hal/camera.hpp"
#include "cambio/hal/image.hpp"
#include "cambio/hal/loop.hpp"
#include "cambio/hal/seqlock_channel.hpp"
#include "cambio/hal/triple_buffer.hpp"
#include "cambio/perception/sensory_servo.hpp"

namespace cambio::perception {

/// What the decision layer wants next: where each eye's retina sits and which features.
struct SsmRequest {
  bool fixation_set = false;  ///< False: each retina is centred on its image.
  std::array<PixelPoint, 2> fixation{};
  FeatureRequest features;
};

/// The SSM as an information server (paper Section 4): a perception loop that grabs both
/// cameras through the HAL, builds the retinas at the requested fixation points, computes the
/// requested features and publishes them on latest-value channels. configure() allocates
/// everything; update() never allocates, locks or blocks beyond the cameras' grab().
class SsmServer final : public hal::Loop {
 public:
  SsmServer(std::string name, hal::Camera& left, hal::Camera& right, SsmConfig config);
  ~SsmServer() override;

  const std::string& name() const override { return name_; }
  /// Sizes the images from the cameras' info and builds the pipeline. Throws
  /// std::invalid_argument if the cameras differ in size or the config is inconsistent.
  void configure() override;
  void activate() override;
  /// kNoNewData when neither camera had a new frame; kRejected when not configured or a grab
  /// was refused. Real-time safe.
  hal::Status update(const hal::LoopTick& tick) noexcept override;

  /// Written by the decision layer (one writer), read here each cycle.
  hal::SeqlockChannel<SsmRequest>& requests() { return requests_; }
  /// The newest summary (disparity, motion, moments). Any number of readers.
  const hal::SeqlockChannel<SsmSummary>& summaries() const { return summaries_; }
  /// The newest full frame with feature maps (one reader). Valid after configure().
  hal::TripleBuffer<SsmFrame>& frames() { return *frames_; }

 private:
  std::string name_;
  hal::Camera& left_camera_;
  hal::Camera& right_camera_;
  SsmConfig config_;
  hal::Image left_image_;
  hal::Image right_image_;
  std::unique_ptr<SensoryServo> servo_;
  std::unique_ptr<hal::TripleBuffer<SsmFrame>> frames_;
  hal::SeqlockChannel<SsmRequest> requests_;
  hal::SeqlockChannel<SsmSummary> summaries_;
};

}  // namespace cambio::perception
