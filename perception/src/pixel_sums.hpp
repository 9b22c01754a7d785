#pragma once

// The retina's inner loops: sums of source pixels (grey bytes, or rgb8 through hal::luma_bt601)
// down columns and along rows, each built for AVX2 and for the baseline target, chosen at load
// time. Internal to the perception library.

#include <cstddef>
#include <cstdint>

#include "cambio/hal/luma.hpp"

namespace cambio::perception::pixel_sums {

/// A column sum of b rows of bytes fits 16 bits while b * 255 < 2^16: twice the lanes per add.
constexpr int kMaxRows16 = 257;

template <int kChannels>
inline unsigned pixel_at(const std::uint8_t* row, int x) {
  if constexpr (kChannels == 3) {
    return hal::luma_bt601(row[3 * x], row[3 * x + 1], row[3 * x + 2]);
  } else {
    return row[x];
  }
}

// The sum of n pixels from p: grey bytes in fixed runs of 32 the compiler vectorises (a counted
// loop of unknown length it leaves scalar at -O2), or luma through hal::luma_bt601.
template <int kChannels>
[[gnu::always_inline]] inline std::uint32_t sum_pixels_impl(const std::uint8_t* __restrict p,
                                                            int n) {
  std::uint32_t total = 0;
  int i = 0;
  if constexpr (kChannels == 1) {
    constexpr int kRun = 32;
    for (; i + kRun <= n; i += kRun) {
      std::uint32_t run = 0;
      for (int j = 0; j < kRun; ++j) run += p[i + j];
      total += run;
    }
  }
  for (; i < n; ++i) total += pixel_at<kChannels>(p, i);
  return total;
}

/// Adds `weight` times one source row of `count` pixels to the column sums.
void add_row(std::uint32_t* sums, const std::uint8_t* row, int count, unsigned weight, bool rgb);
void add_row(std::uint16_t* sums, const std::uint8_t* row, int count, unsigned weight, bool rgb);

/// Sets sums[i] to the sum over `rows` rows (from `top`, `stride` bytes apart) of pixel i.
void sum_rows(std::uint32_t* sums, const std::uint8_t* top, std::ptrdiff_t stride, int rows,
              int count, bool rgb);
void sum_rows(std::uint16_t* sums, const std::uint8_t* top, std::ptrdiff_t stride, int rows,
              int count, bool rgb);

/// out[i] = norm times the sum of sums[i * scale, (i + 1) * scale).
void reduce_blocks(const std::uint32_t* sums, float* out, int count, int scale, float norm);
void reduce_blocks(const std::uint16_t* sums, float* out, int count, int scale, float norm);

/// The sum of n grey bytes from p.
std::uint32_t sum_grey(const std::uint8_t* p, int n);

}  // namespace cambio::perception::pixel_sums
