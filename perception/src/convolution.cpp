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
// width) run as one long 1-D loop per tap. target_clones builds an AVX2 version next to
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

// Strips of 16 outputs (four 4-float vectors) with the sums held in registers for every tap:
// each tap step is one load per side and one multiply-add per output vector, with no reload or
// store of the output and no aliasing checks. kOdd odd masks and kEven even masks of the same half
// width share the loads and the folded lo - hi / lo + hi, so one pass over the input feeds up
// to three outputs. Per output the operation order is the one of convolve_line. 16-byte vectors
// on purpose: the default (SSE2) clone must stay fast too, and 32-byte generic vectors lower badly
// there. The clones dispatch on the avx2 feature (not on a CPU model such as arch=haswell, which
// never matched this Xeon and left the AVX2 clone unused).
using Vec4 = float __attribute__((vector_size(16)));

[[gnu::always_inline]] inline Vec4 load4(const float* p) {
  Vec4 v;
  __builtin_memcpy(&v, p, sizeof v);
  return v;
}

[[gnu::always_inline]] inline void store4(float* p, Vec4 v) {
  __builtin_memcpy(p, &v, sizeof v);
}

constexpr int kStrip = 16;
constexpr int kLanes = 4;
constexpr int kParts = kStrip / kLanes;

template <int kOdd, int kEven>
[[gnu::always_inline]] inline void folded_strips(const float* in, std::ptrdiff_t in_stride,
                                                 std::ptrdiff_t unit, float* const* out,
                                                 std::ptrdiff_t out_stride, int width, int height,
                                                 const float* const* c, int s) {
  constexpr int kOut = kOdd + kEven;
  for (int y = 0; y < height; ++y) {
    for (int x = 0; x < width; x += kStrip) {
      const float* p = in + y * in_stride + x;
      Vec4 acc[kOut][kParts];
      for (int v = 0; v < kParts; ++v) {
        const Vec4 m = load4(p + v * kLanes);
        for (int j = 0; j < kOut; ++j) acc[j][v] = c[j][0] * m;
      }
      for (int t = 1; t <= s; ++t) {
        const float* lo = p - t * unit;
        const float* hi = p + t * unit;
        for (int v = 0; v < kParts; ++v) {
          const Vec4 l = load4(lo + v * kLanes);
          const Vec4 h = load4(hi + v * kLanes);
          if constexpr (kOdd > 0) {
            const Vec4 d = l - h;
            for (int j = 0; j < kOdd; ++j) acc[j][v] += c[j][t] * d;
          }
          if constexpr (kEven > 0) {
            const Vec4 e = l + h;
            for (int j = kOdd; j < kOut; ++j) acc[j][v] += c[j][t] * e;
          }
        }
      }
      for (int j = 0; j < kOut; ++j) {
        float* q = out[j] + y * out_stride + x;
        for (int v = 0; v < kParts; ++v) store4(q + v * kLanes, acc[j][v]);
      }
    }
  }
}

// The strip path for one mask; false when it does not apply (asymmetric mask, width not a
// multiple of the strip).
[[gnu::always_inline]] inline bool strips_one(const float* in, std::ptrdiff_t in_stride,
                                              std::ptrdiff_t unit, float* out,
                                              std::ptrdiff_t out_stride, int width, int height,
                                              const Taps& taps) {
  if (width % kStrip != 0 || taps.symmetry == Symmetry::kNone) return false;
  const float* c[1] = {taps.centre()};
  float* o[1] = {out};
  if (taps.symmetry == Symmetry::kOdd) {
    folded_strips<1, 0>(in, in_stride, unit, o, out_stride, width, height, c, taps.half_width);
  } else {
    folded_strips<0, 1>(in, in_stride, unit, o, out_stride, width, height, c, taps.half_width);
  }
  return true;
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

__attribute__((target_clones("avx2", "default"))) void convolve_rows(
    const float* in, std::ptrdiff_t in_stride, float* out, std::ptrdiff_t out_stride, int width,
    int height, const Taps& taps) noexcept {
  if (strips_one(in, in_stride, 1, out, out_stride, width, height, taps)) return;
  convolve_any(in, in_stride, 1, out, out_stride, width, height, taps);
}

__attribute__((target_clones("avx2", "default"))) void convolve_columns(
    const float* in, std::ptrdiff_t in_stride, float* out, std::ptrdiff_t out_stride, int width,
    int height, const Taps& taps) noexcept {
  if (in_stride == width && out_stride == width && (width * height) % kStrip == 0) {
    // Packed planes: one long line of width * height outputs.
    if (strips_one(in, 0, in_stride, out, 0, width * height, 1, taps)) return;
  } else if (strips_one(in, in_stride, in_stride, out, out_stride, width, height, taps)) {
    return;
  }
  if (in_stride == width && out_stride == width) {
    // Packed planes: rows y - t and y + t of the whole plane are one contiguous run each.
    convolve_line<0>(in, in_stride, out, width * height, taps.centre(), taps.half_width,
                     taps.symmetry);
    return;
  }
  convolve_any(in, in_stride, in_stride, out, out_stride, width, height, taps);
}

__attribute__((target_clones("avx2", "default"))) bool convolve_rows_family(
    const float* in, std::ptrdiff_t in_stride, std::ptrdiff_t out_stride, int width, int height,
    const Taps& odd, float* odd_out, const Taps& even_a, float* even_a_out, const Taps& even_b,
    float* even_b_out) noexcept {
  if (width % kStrip != 0 || odd.symmetry != Symmetry::kOdd || even_a.symmetry != Symmetry::kEven ||
      even_b.symmetry != Symmetry::kEven || odd.half_width != even_a.half_width ||
      odd.half_width != even_b.half_width) {
    return false;
  }
  const float* c[3] = {odd.centre(), even_a.centre(), even_b.centre()};
  float* o[3] = {odd_out, even_a_out, even_b_out};
  folded_strips<1, 2>(in, in_stride, 1, o, out_stride, width, height, c, odd.half_width);
  return true;
}

__attribute__((target_clones("avx2", "default"))) bool convolve_columns_pair(
    const float* in, std::ptrdiff_t in_stride, std::ptrdiff_t out_stride, int width, int height,
    const Taps& odd, float* odd_out, const Taps& even, float* even_out) noexcept {
  if (width % kStrip != 0 || odd.symmetry != Symmetry::kOdd || even.symmetry != Symmetry::kEven ||
      odd.half_width != even.half_width) {
    return false;
  }
  const float* c[2] = {odd.centre(), even.centre()};
  float* o[2] = {odd_out, even_out};
  folded_strips<1, 1>(in, in_stride, in_stride, o, out_stride, width, height, c, odd.half_width);
  return true;
}

__attribute__((target_clones("avx2", "default"))) void correlate_2d(
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
