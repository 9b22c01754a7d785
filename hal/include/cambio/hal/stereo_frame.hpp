#pragma once

#include <cstdint>
#include <cstdlib>

#include "cambio/hal/image.hpp"

namespace cambio::hal {

/// Both eyes' images of one camera-loop cycle, published as one unit so a consumer never pairs
/// a new left image with an old right one. Each image keeps its own stamp and sequence.
struct StereoFrame {
  Image left;
  Image right;

  /// |left.stamp - right.stamp| (ns).
  std::int64_t stamp_skew_ns() const { return std::llabs(left.stamp_ns - right.stamp_ns); }
  bool complete() const { return left.sequence != 0 && right.sequence != 0; }
};

}  // namespace cambio::hal
