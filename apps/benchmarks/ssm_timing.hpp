#pragma once

// perception-bench's timing of the Sensory Servo Module on one stereo pair.

#include <cstdint>

#include "cambio/hal/image.hpp"
#include "cambio/perception/sensory_servo.hpp"

namespace cambio::app {

/// Medians over the timed runs: the whole SSM and each of its parts; its disparity at the fovea.
struct SsmFigures {
  double total_us = 0;
  perception::SsmTimings parts;
  float disparity_px = 0;
  float confidence = 0;
};

/// Where each run fixates: the image centre (as the robot's SSM does by default), or a new place
/// every run (a behaviour moving the fovea around the image: through a lens, each place's
/// footprints are planned anew).
enum class Fixations : std::uint8_t { kCentre, kNewEveryRun };

/// One SSM and its output frame, processing the pair. Keeps references to the images.
class SsmRun {
 public:
  /// With a `lens`, both eyes' retinas read the pair through it (SensoryServo::set_lenses).
  SsmRun(const perception::SsmConfig& config, const hal::Image& left, const hal::Image& right,
         const perception::LensDistortion* lens = nullptr,
         Fixations fixations = Fixations::kCentre);
  /// Throws std::runtime_error when the SSM rejects the pair.
  const perception::SsmFrame& run();
  const perception::SsmFrame& frame() const { return frame_; }

 private:
  perception::SensoryServo servo_;
  perception::SsmFrame frame_;
  const hal::Image& left_;
  const hal::Image& right_;
  Fixations fixations_;
  int runs_ = 0;
};

/// Warm: the pair stays in the caches from run to run. Fresh: every cache level is flushed
/// before each run, as in the robot's loop, where a pair arrives from the cameras, rendered or
/// DMA'd, not warm from the previous run over the same pair.
enum class Frames : std::uint8_t { kWarm, kFresh };

/// The SSM's median over `repeats` runs on the pair; with Frames::kFresh the caches are evicted
/// before each run (outside the timed span).
SsmFigures time_ssm(const perception::SsmConfig& config, const hal::Image& left,
                    const hal::Image& right, int repeats, Frames frames = Frames::kWarm,
                    const perception::LensDistortion* lens = nullptr,
                    Fixations fixations = Fixations::kCentre);

}  // namespace cambio::app
