#pragma once

// perception-bench's input: one synthetic 640x480 stereo pair with a known disparity.

#include "cambio/hal/image.hpp"

namespace cambio::app {

inline constexpr int kBenchPairWidthPx = 640;
inline constexpr int kBenchPairHeightPx = 480;
/// The right image is the left one shifted by this much, px.
inline constexpr double kBenchPairDisparityPx = 3.3;

struct BenchStereoPair {
  hal::Image left;  ///< grey8
  hal::Image right;
  hal::Image left_rgb;  ///< rgb8 whose luma is `left`
  hal::Image right_rgb;
};

/// A textured pair (48 cosine waves of random direction, band-limited so that sub-pixel shifts
/// are exact), the same every call (a fixed seed).
BenchStereoPair make_bench_pair();

/// Horizontal stripes (cosines of y only, periods 6 to 40 px), the right image the left shifted
/// by kBenchPairDisparityPx: every horizontal shift matches alike (the aperture problem), so the
/// disparity scan scores the whole range with every window it has: its worst case for time.
BenchStereoPair make_horizontal_stripes_pair();

}  // namespace cambio::app
