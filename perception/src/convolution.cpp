#include "cambio/perception/convolution.hpp"

namespace cambio::perception {

Taps Taps::from(const std::vector<double>& taps) {
  Taps result;
  result.half_width = static_cast<int>(taps.size() / 2);
  result.values.assign(taps.begin(), taps.end());
  bool even = true;
  bool odd = true;
  const std::size_t n = result.values.size();
  for (std::size_t i = 0; i < n; ++i) {
    even = even && result.values[i] == result.values[n - 1 - i];
    odd = odd && result.values[i] == -result.values[n - 1 - i];
  }
  result.symmetry = even ? Symmetry::kEven : (odd ? Symmetry::kOdd : Symmetry::kNone);
  return result;
}

// The passes below run on a few rows of 16 to 64 floats. Loops keep x innermost so they
// vectorise, each tap pair is folded (even/odd masks) to halve the multiplications, and the
// common retina widths are compile-time constants so each (row, tap) step is a few whole
// vector instructions with no loop overhead. Column passes over packed planes (stride ==
// width) run as one long 1-D loop per tap. target_clones builds an AVX2/FMA version next to
// the baseline one, chosen at load time.
namespace {

template <int kWidth>
[[gnu::always_inline]] inline void convolve_line(const float* __restrict in, std::ptrdiff_t unit,
                                                 float* __restrict out, int runtime_width,
                                                 const float* __restrict c, int s,
                                                 Symmetry symmetry) {
  const int width = kWidth > 0 ? kWidth : runtime_width;
  for (int x = 0; x < width; ++x) out[x] = c[0] * in[x];
  switch (symmetry) {
    case Symmetry::kEven:
      for (int t = 1; t <= s; ++t) {
        const float k = c[t];
        const float* lo = in - t * unit;
        const float* hi = in + t * unit;
        for (int x = 0; x < width; ++x) out[x] += k * (lo[x] + hi[x]);
      }
      break;
    case Symmetry::kOdd:
      for (int t = 1; t <= s; ++t) {
        const float k = c[t];
        const float* lo = in - t * unit;
        const float* hi = in + t * unit;
        for (int x = 0; x < width; ++x) out[x] += k * (lo[x] - hi[x]);
      }
      break;
    case Symmetry::kNone:
      for (int t = -s; t <= s; ++t) {
        if (t == 0) continue;
        const float k = c[t];
        const float* src = in - t * unit;
        for (int x = 0; x < width; ++x) out[x] += k * src[x];
      }
      break;
  }
}

template <int kWidth>
[[gnu::always_inline]] inline void convolve_lines(const float* in, std::ptrdiff_t in_stride,
                                                  std::ptrdiff_t unit, float* out,
                                                  std::ptrdiff_t out_stride, int width, int height,
                                                  const Taps& taps) {
  for (int y = 0; y < height; ++y) {
    convolve_line<kWidth>(in + y * in_stride, unit, out + y * out_stride, width, taps.centre(),
                          taps.half_width, taps.symmetry);
  }
}

[[gnu::always_inline]] inline void convolve_any(const float* in, std::ptrdiff_t in_stride,
                                                std::ptrdiff_t unit, float* out,
                                                std::ptrdiff_t out_stride, int width, int height,
                                                const Taps& taps) {
  switch (width) {
    case 16:
      convolve_lines<16>(in, in_stride, unit, out, out_stride, width, height, taps);
      break;
    case 32:
      convolve_lines<32>(in, in_stride, unit, out, out_stride, width, height, taps);
      break;
    case 64:
      convolve_lines<64>(in, in_stride, unit, out, out_stride, width, height, taps);
      break;
    default:
      convolve_lines<0>(in, in_stride, unit, out, out_stride, width, height, taps);
      break;
  }
}

}  // namespace

__attribute__((target_clones("arch=haswell", "default"))) void convolve_rows(
    const float* in, std::ptrdiff_t in_stride, float* out, std::ptrdiff_t out_stride, int width,
    int height, const Taps& taps) noexcept {
  convolve_any(in, in_stride, 1, out, out_stride, width, height, taps);
}

__attribute__((target_clones("arch=haswell", "default"))) void convolve_columns(
    const float* in, std::ptrdiff_t in_stride, float* out, std::ptrdiff_t out_stride, int width,
    int height, const Taps& taps) noexcept {
  if (in_stride == width && out_stride == width) {
    // Packed planes: rows y - t and y + t of the whole plane are one contiguous run each.
    convolve_line<0>(in, in_stride, out, width * height, taps.centre(), taps.half_width,
                     taps.symmetry);
    return;
  }
  convolve_any(in, in_stride, in_stride, out, out_stride, width, height, taps);
}

__attribute__((target_clones("arch=haswell", "default"))) void correlate_2d(
    const float* in, std::ptrdiff_t in_stride, float* out, std::ptrdiff_t out_stride, int width,
    int height, const float* mask, int rows, int cols) noexcept {
  const int r0 = rows / 2;
  const int c0 = cols / 2;
  for (int y = 0; y < height; ++y) {
    float* __restrict o = out + y * out_stride;
    for (int x = 0; x < width; ++x) o[x] = 0.0f;
    for (int r = 0; r < rows; ++r) {
      const float* src = in + (y + r - r0) * in_stride - c0;
      for (int c = 0; c < cols; ++c) {
        const float k = mask[r * cols + c];
        const float* __restrict s = src + c;
        for (int x = 0; x < width; ++x) o[x] += k * s[x];
      }
    }
  }
}

}  // namespace cambio::perception
