#pragma once

// sim-bench's camera figures: the stereo frames per second of the sim's camera pipeline (render,
// read back, flip, convert, noise: what Camera::grab does) on whole and on foveated frames,
// against a raw MuJoCo render-and-read loop of the same scene on the same GL context.

#include <optional>

#include "cambio/config/rig_config.hpp"
#include "cambio/hal/image.hpp"
#include "cambio/sim/sim_backend.hpp"

namespace cambio::app {

struct CameraFigures {
  int width_px = 0;
  int height_px = 0;
  hal::PixelFormat format = hal::PixelFormat::kGrey8;
  double camera_fps = 0.0;  ///< Whole frames through the HAL, stereo pairs per second.
  double raw_fps = 0.0;     ///< The raw MuJoCo loop, stereo pairs per second.
  double camera_vs_raw = 0.0;
  std::optional<double> foveated_fps;  ///< Set when there was a foveated backend.
  std::optional<double> foveated_vs_raw;
  int rounds = 0;  ///< The ratios are the medians of this many rounds' ratios.
};

/// Measures the pipeline of `whole_backend` (whole frames) and, if given, of `foveated_backend`,
/// against the raw loop on `whole_backend`'s renderer, alternated in short rounds that share
/// `seconds` of wall time so that all see the same machine load. Activates the backends; a
/// physics step between pairs makes every pair a new frame and is not counted. `rig` names the
/// stereo pair. Throws std::runtime_error when a grab fails.
CameraFigures measure_cameras(sim::SimBackend& whole_backend, sim::SimBackend* foveated_backend,
                              const config::RigConfig& rig, double seconds);

}  // namespace cambio::app
