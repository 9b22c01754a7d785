#pragma once

// `cambio perception-bench`'s measurement: the paper's claim, measured on one 640x480 stereo
// pair. The whole SSM (retinas, every operator at 3 sigmas, disparity, motion, moments) for the
// paper's 4 x 16 x 16 retina (its coarsest level covering the whole field) on grey and on rgb8
// frames, for the same retina without the field-covering level (fovea only) and for 4 x 64 x 64;
// a memcpy of both images (the memory bound), alternated with the paper's SSM in rounds; the same
// operator set on the full images with cv::sepFilter2D (the "filter everything" approach); and
// cv::StereoBM on the full pair. Every figure is the median time per stereo pair.

namespace cambio::app {

struct PerceptionBenchOptions {
  /// Timed runs per figure, at least 5; the 64x64 SSM, fresh frames and OpenCV use repeats / 5,
  /// each alternated round repeats / 11 (at least 5 each).
  int repeats = 300;
  bool json = false;  ///< One JSON object instead of a table.
};

/// Measures and prints the figures; OpenCV is set to one thread for the rest of the process.
/// Returns the exit status. Throws std::runtime_error when the SSM rejects the pair.
int run_perception_bench(const PerceptionBenchOptions& options);

}  // namespace cambio::app
