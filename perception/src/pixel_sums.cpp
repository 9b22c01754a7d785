#include "pixel_sums.hpp"

#include <algorithm>

namespace cambio::perception::pixel_sums {

// Adds `weight` times one source row to the column sums: grey pixels as they are, rgb8 pixels
// through hal::luma_bt601, so only the pixels a level reads are converted, inside the sum, and a
// colour frame gives exactly the levels of its grey conversion. The weight of a replicated edge
// row is the count of rows beyond the edge that map onto it.
template <typename Sum>
[[gnu::always_inline]] inline void accumulate_row(Sum* __restrict sums,
                                                  const std::uint8_t* __restrict row, int count,
                                                  unsigned weight, bool rgb) {
  if (rgb) {
    if (weight == 1) {
      for (int i = 0; i < count; ++i) {
        sums[i] =
            static_cast<Sum>(sums[i] + hal::luma_bt601(row[3 * i], row[3 * i + 1], row[3 * i + 2]));
      }
    } else {
      for (int i = 0; i < count; ++i) {
        sums[i] = static_cast<Sum>(
            sums[i] + weight * hal::luma_bt601(row[3 * i], row[3 * i + 1], row[3 * i + 2]));
      }
    }
  } else if (weight == 1) {
    for (int i = 0; i < count; ++i) sums[i] = static_cast<Sum>(sums[i] + row[i]);
  } else {
    for (int i = 0; i < count; ++i) sums[i] = static_cast<Sum>(sums[i] + weight * row[i]);
  }
}

__attribute__((target_clones("avx2", "default"))) void add_row(std::uint32_t* __restrict sums,
                                                               const std::uint8_t* __restrict row,
                                                               int count, unsigned weight,
                                                               bool rgb) {
  accumulate_row(sums, row, count, weight, rgb);
}

__attribute__((target_clones("avx2", "default"))) void add_row(std::uint16_t* __restrict sums,
                                                               const std::uint8_t* __restrict row,
                                                               int count, unsigned weight,
                                                               bool rgb) {
  accumulate_row(sums, row, count, weight, rgb);
}

// Sets sums[i] to the sum over `rows` rows (from `top`, `stride` bytes apart) of pixel i, grey or
// through hal::luma_bt601: one call per block row, each strip of columns summed down all rows
// while its sums stay in registers, so a tall block (a field-covering level's 40 rows at
// 640 x 480) costs a load and an add per pixel, not a row call and a store.
template <typename Sum, int kChannels>
[[gnu::always_inline]] inline void sum_rows_impl(Sum* __restrict sums,
                                                 const std::uint8_t* __restrict top,
                                                 std::ptrdiff_t stride, int rows, int count) {
  const auto pixel = [](const std::uint8_t* p, int i) -> unsigned {
    if constexpr (kChannels == 3) {
      return hal::luma_bt601(p[3 * i], p[3 * i + 1], p[3 * i + 2]);
    } else {
      return p[i];
    }
  };
  constexpr int kStrip = 64;
  int x = 0;
  for (; x + kStrip <= count; x += kStrip) {
    Sum acc[kStrip] = {};
    const std::uint8_t* p = top + static_cast<std::ptrdiff_t>(x) * kChannels;
    for (int y = 0; y < rows; ++y, p += stride) {
      for (int i = 0; i < kStrip; ++i) acc[i] = static_cast<Sum>(acc[i] + pixel(p, i));
    }
    for (int i = 0; i < kStrip; ++i) sums[x + i] = acc[i];
  }
  if (x == count) return;
  std::fill(sums + x, sums + count, Sum{0});
  const std::uint8_t* p = top + static_cast<std::ptrdiff_t>(x) * kChannels;
  for (int y = 0; y < rows; ++y, p += stride) {
    for (int i = 0; i < count - x; ++i) sums[x + i] = static_cast<Sum>(sums[x + i] + pixel(p, i));
  }
}

__attribute__((target_clones("avx2", "default"))) void sum_rows(std::uint32_t* __restrict sums,
                                                                const std::uint8_t* __restrict top,
                                                                std::ptrdiff_t stride, int rows,
                                                                int count, bool rgb) {
  if (rgb) {
    sum_rows_impl<std::uint32_t, 3>(sums, top, stride, rows, count);
  } else {
    sum_rows_impl<std::uint32_t, 1>(sums, top, stride, rows, count);
  }
}

__attribute__((target_clones("avx2", "default"))) void sum_rows(std::uint16_t* __restrict sums,
                                                                const std::uint8_t* __restrict top,
                                                                std::ptrdiff_t stride, int rows,
                                                                int count, bool rgb) {
  if (rgb) {
    sum_rows_impl<std::uint16_t, 3>(sums, top, stride, rows, count);
  } else {
    sum_rows_impl<std::uint16_t, 1>(sums, top, stride, rows, count);
  }
}

// A compile-time block width: the block sum is a fixed run of adds the compiler turns into
// whole-vector loads and a short horizontal reduction instead of a counted inner loop.
template <int kScale, typename Sum>
[[gnu::always_inline]] inline void reduce_fixed(const Sum* __restrict sums, float* __restrict out,
                                                int count, float norm) {
  for (int i = 0; i < count; ++i) {
    std::uint32_t total = 0;
    const Sum* block = sums + static_cast<std::ptrdiff_t>(i) * kScale;
    for (int j = 0; j < kScale; ++j) total += block[j];
    out[i] = static_cast<float>(total) * norm;
  }
}

template <typename Sum>
[[gnu::always_inline]] inline void reduce_any(const Sum* __restrict sums, float* __restrict out,
                                              int count, int scale, float norm) {
  switch (scale) {
    case 1:
      for (int i = 0; i < count; ++i) out[i] = static_cast<float>(sums[i]) * norm;
      return;
    case 2:
      reduce_fixed<2>(sums, out, count, norm);
      return;
    case 4:
      reduce_fixed<4>(sums, out, count, norm);
      return;
    case 8:
      reduce_fixed<8>(sums, out, count, norm);
      return;
    case 16:
      reduce_fixed<16>(sums, out, count, norm);
      return;
    default:
      break;
  }
  for (int i = 0; i < count; ++i) {
    std::uint32_t total = 0;
    const Sum* block = sums + static_cast<std::ptrdiff_t>(i) * scale;
    for (int j = 0; j < scale; ++j) total += block[j];
    out[i] = static_cast<float>(total) * norm;
  }
}

__attribute__((target_clones("avx2", "default"))) void reduce_blocks(
    const std::uint32_t* __restrict sums, float* __restrict out, int count, int scale, float norm) {
  reduce_any(sums, out, count, scale, norm);
}

__attribute__((target_clones("avx2", "default"))) void reduce_blocks(
    const std::uint16_t* __restrict sums, float* __restrict out, int count, int scale, float norm) {
  reduce_any(sums, out, count, scale, norm);
}

__attribute__((target_clones("avx2", "default"))) std::uint32_t sum_grey(
    const std::uint8_t* __restrict p, int n) {
  return sum_pixels_impl<1>(p, n);
}

}  // namespace cambio::perception::pixel_sums
