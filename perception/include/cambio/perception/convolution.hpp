#pragma once

#include <cstddef>
#include <vector>

namespace cambio::perception {

/// Symmetry of a 1-D mask, used to halve the multiplications.
enum class Symmetry { kEven, kOdd, kNone };

/// A 1-D convolution mask of 2 half_width + 1 float taps, index 0 at -half_width.
struct Taps {
  std::vector<float> values;
  int half_width = 0;
  Symmetry symmetry = Symmetry::kNone;

  /// Rounds to float and detects exact (even/odd) symmetry.
  static Taps from(const std::vector<double>& taps);
  const float* centre() const { return values.data() + half_width; }
};

/// out(x, y) = sum_t k(t) in(x - t, y) for x in [0, width), y in [0, height). `in` points at the
/// sample aligned with out(0, 0); in[-half_width .. width - 1 + half_width] of each row is read.
/// Real-time safe.
void convolve_rows(const float* in, std::ptrdiff_t in_stride, float* out, std::ptrdiff_t out_stride,
                   int width, int height, const Taps& taps) noexcept;

/// out(x, y) = sum_t k(t) in(x, y - t); rows -half_width .. height - 1 + half_width are read.
void convolve_columns(const float* in, std::ptrdiff_t in_stride, float* out,
                      std::ptrdiff_t out_stride, int width, int height, const Taps& taps) noexcept;

/// Three row passes in one over the same rows: an odd mask and two even masks of one half
/// width (a Gaussian family's order 1, order 2 and across), sharing the loads and folded sums.
/// Each output equals convolve_rows with its mask. Returns false, touching nothing, unless the
/// symmetries and half widths match and width is a multiple of 16.
bool convolve_rows_family(const float* in, std::ptrdiff_t in_stride, std::ptrdiff_t out_stride,
                          int width, int height, const Taps& odd, float* odd_out,
                          const Taps& even_a, float* even_a_out, const Taps& even_b,
                          float* even_b_out) noexcept;

/// Two column passes in one over the same input: an odd and an even mask of one half width.
/// Each output equals convolve_columns with its mask. Returns false, touching nothing, unless
/// the symmetries and half widths match and width is a multiple of 16.
bool convolve_columns_pair(const float* in, std::ptrdiff_t in_stride, std::ptrdiff_t out_stride,
                           int width, int height, const Taps& odd, float* odd_out, const Taps& even,
                           float* even_out) noexcept;

/// out(x, y) = sum_{r,c} mask(r, c) in(x + c - cols/2, y + r - rows/2): a mask applied as
/// written (correlation), as cv::filter2D does. Real-time safe.
void correlate_2d(const float* in, std::ptrdiff_t in_stride, float* out, std::ptrdiff_t out_stride,
                  int width, int height, const float* mask, int rows, int cols) noexcept;

}  // namespace cambio::perception
