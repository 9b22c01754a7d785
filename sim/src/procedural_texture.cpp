#include "cambio/sim/procedural_texture.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <random>
#include <vector>

namespace cambio::sim {

namespace {

std::uint8_t to_byte(double value) {
  return static_cast<std::uint8_t>(std::clamp(std::lround(value * 255.0), 0L, 255L));
}

// Mixes the two colours by t in [0, 1] into texel i.
void put(std::span<std::uint8_t> out, std::size_t texel, const std::array<double, 3>& a,
         const std::array<double, 3>& b, double t) {
  for (std::size_t c = 0; c < 3; ++c) out[texel * 3 + c] = to_byte(a[c] + (b[c] - a[c]) * t);
}

double smooth(double t) {
  return t * t * (3.0 - 2.0 * t);
}

// Periodic value noise: a random lattice of `cells_x` x `cells_y` cells, smoothly interpolated,
// wrapping at the texture's edges so tiled copies meet without a seam.
class ValueNoise {
 public:
  ValueNoise(int cells_x, int cells_y, std::mt19937_64& rng)
      : cells_x_(std::max(1, cells_x)),
        cells_y_(std::max(1, cells_y)),
        lattice_(static_cast<std::size_t>(cells_x_) * static_cast<std::size_t>(cells_y_)) {
    std::uniform_real_distribution<double> uniform(0.0, 1.0);
    for (auto& value : lattice_) value = uniform(rng);
  }
  // (u, v) in lattice cells.
  double at(double u, double v) const {
    const int x0 = static_cast<int>(std::floor(u));
    const int y0 = static_cast<int>(std::floor(v));
    const double fx = smooth(u - x0);
    const double fy = smooth(v - y0);
    const double a = lattice(x0, y0) + (lattice(x0 + 1, y0) - lattice(x0, y0)) * fx;
    const double b = lattice(x0, y0 + 1) + (lattice(x0 + 1, y0 + 1) - lattice(x0, y0 + 1)) * fx;
    return a + (b - a) * fy;
  }

 private:
  double lattice(int x, int y) const {
    x = ((x % cells_x_) + cells_x_) % cells_x_;
    y = ((y % cells_y_) + cells_y_) % cells_y_;
    return lattice_[static_cast<std::size_t>(y) * static_cast<std::size_t>(cells_x_) +
                    static_cast<std::size_t>(x)];
  }
  int cells_x_;
  int cells_y_;
  std::vector<double> lattice_;
};

}  // namespace

void fill_procedural_texture(const config::TextureConfig& texture, std::array<double, 3> rgb,
                             double feature_px, int width_px, int height_px,
                             std::span<std::uint8_t> rgb_out) {
  using config::TextureKind;
  const auto& second = texture.second_rgb;
  feature_px = std::max(1.0, feature_px);
  // Features per period are whole numbers so the pattern tiles: round the feature size so that
  // an integer count fits the width and the height.
  const int cells_x = std::max(1, static_cast<int>(std::lround(width_px / feature_px)));
  const int cells_y = std::max(1, static_cast<int>(std::lround(height_px / feature_px)));
  const double cell_w = static_cast<double>(width_px) / cells_x;
  const double cell_h = static_cast<double>(height_px) / cells_y;
  std::mt19937_64 rng(texture.pattern_seed * 0x9E3779B97F4A7C15ULL + 1);

  switch (texture.kind) {
    case TextureKind::kNone:
      for (int i = 0; i < width_px * height_px; ++i)
        put(rgb_out, static_cast<std::size_t>(i), rgb, rgb, 0.0);
      return;
    case TextureKind::kChecker:
      for (int y = 0; y < height_px; ++y) {
        for (int x = 0; x < width_px; ++x) {
          const int parity = (static_cast<int>(x / cell_w) + static_cast<int>(y / cell_h)) % 2;
          put(rgb_out, static_cast<std::size_t>(y * width_px + x), rgb, second, parity);
        }
      }
      return;
    case TextureKind::kStripes:
      // Stripes across x with a soft edge, so they do not alias when seen from afar.
      for (int y = 0; y < height_px; ++y) {
        for (int x = 0; x < width_px; ++x) {
          const double phase = (x + 0.5) / cell_w;
          const double t = 0.5 + 0.5 * std::sin(phase * std::numbers::pi);
          put(rgb_out, static_cast<std::size_t>(y * width_px + x), rgb, second, smooth(t));
        }
      }
      return;
    case TextureKind::kNoise: {
      // Three octaves (1, 1/2 and 1/4 of the feature size) with halving weights: blobs at the
      // feature size with finer detail, which stereo correlation locks onto at every scale.
      const ValueNoise coarse(cells_x, cells_y, rng);
      const ValueNoise middle(cells_x * 2, cells_y * 2, rng);
      const ValueNoise fine(cells_x * 4, cells_y * 4, rng);
      for (int y = 0; y < height_px; ++y) {
        for (int x = 0; x < width_px; ++x) {
          const double u = (x + 0.5) / cell_w;
          const double v = (y + 0.5) / cell_h;
          const double n =
              (4.0 * coarse.at(u, v) + 2.0 * middle.at(2 * u, 2 * v) + fine.at(4 * u, 4 * v)) / 7.0;
          // Stretch the contrast (sums of uniforms crowd around 0.5).
          put(rgb_out, static_cast<std::size_t>(y * width_px + x), rgb, second,
              std::clamp((n - 0.5) * 2.2 + 0.5, 0.0, 1.0));
        }
      }
      return;
    }
    case TextureKind::kChessboard: {
      // The board centred on each square face (a cube texture stacks six: height = 6 x width),
      // in the second colour and the object's, on a margin of the object's colour; the squares'
      // edges are antialiased by the area of each texel they cover.
      const int face = width_px;
      const double board_w = texture.squares[0] * feature_px;
      const double board_h = texture.squares[1] * feature_px;
      const double left = 0.5 * (face - board_w);
      const double top = 0.5 * (face - board_h);
      for (int y = 0; y < height_px; ++y) {
        for (int x = 0; x < width_px; ++x) {
          double dark = 0.0;  // Share of the texel on dark squares, over 4 x 4 sub-samples.
          for (int sy = 0; sy < 4; ++sy) {
            for (int sx = 0; sx < 4; ++sx) {
              const double u = (x + (sx + 0.5) / 4.0 - left) / feature_px;
              const double v = (y % face + (sy + 0.5) / 4.0 - top) / feature_px;
              if (u < 0.0 || v < 0.0 || u >= texture.squares[0] || v >= texture.squares[1]) {
                continue;
              }
              dark += (static_cast<int>(u) + static_cast<int>(v)) % 2 == 0 ? 1.0 / 16.0 : 0.0;
            }
          }
          put(rgb_out, static_cast<std::size_t>(y * width_px + x), rgb, second, dark);
        }
      }
      return;
    }
    case TextureKind::kDots: {
      for (int i = 0; i < width_px * height_px; ++i)
        put(rgb_out, static_cast<std::size_t>(i), rgb, rgb, 0.0);
      // One dot per cell at a random place, radius 0.25..0.45 of the feature, wrapping around.
      std::uniform_real_distribution<double> uniform(0.0, 1.0);
      for (int cy = 0; cy < cells_y; ++cy) {
        for (int cx = 0; cx < cells_x; ++cx) {
          const double centre_x = (cx + uniform(rng)) * cell_w;
          const double centre_y = (cy + uniform(rng)) * cell_h;
          const double radius = (0.25 + 0.2 * uniform(rng)) * std::min(cell_w, cell_h);
          const int r = static_cast<int>(std::ceil(radius)) + 1;
          for (int dy = -r; dy <= r; ++dy) {
            for (int dx = -r; dx <= r; ++dx) {
              const int x = static_cast<int>(centre_x) + dx;
              const int y = static_cast<int>(centre_y) + dy;
              const double d = std::hypot(x + 0.5 - centre_x, y + 0.5 - centre_y);
              const double t = std::clamp(radius + 0.5 - d, 0.0, 1.0);  // Antialiased edge.
              if (t <= 0.0) continue;
              const int wx = ((x % width_px) + width_px) % width_px;
              const int wy = ((y % height_px) + height_px) % height_px;
              put(rgb_out, static_cast<std::size_t>(wy * width_px + wx), rgb, second, t);
            }
          }
        }
      }
      return;
    }
  }
}

}  // namespace cambio::sim
