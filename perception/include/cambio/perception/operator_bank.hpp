#pragma once

#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

#include "cambio/perception/convolution.hpp"
#include "cambio/perception/gaussian_kernels.hpp"
#include "cambio/perception/perception_config.hpp"
#include "cambio/perception/retina.hpp"

namespace cambio::perception {

/// What one feature map is.
enum class MapKind {
  kIntensity,  ///< The retina level itself.
  kGaussian,   ///< G_d^(k) of Eq. 2-5 for one sigma.
  kLaplacian,  ///< G_x^(2) + G_y^(2): the Laplacian of Gaussian made of Eq. 5's masks.
  kSobelX,     ///< d/dx, positive where intensity rises to the right.
  kSobelY,     ///< d/dy, positive where intensity rises downwards.
  kAverage,    ///< Box mean of (2r+1)^2.
  kUserMask,   ///< A mask from config, applied as written.
};

struct MapSpec {
  std::string name;  ///< e.g. "g2x@1.4", "log@2.7", "sobel_x", "average", or the mask's name.
  MapKind kind = MapKind::kIntensity;
  int order = 0;         ///< Gaussian order 0..2.
  Axis axis = Axis::kX;  ///< Gaussian direction.
  double sigma_px = 0.0;
};

/// Names of the maps a config produces, in output order (map 0 is "intensity").
std::vector<MapSpec> feature_map_specs(const OperatorConfig& config);

/// A request: bit i asks for map i of feature_map_specs(). At most kMaxMaps maps.
using MapMask = std::uint64_t;
inline constexpr int kMaxMaps = 64;
inline constexpr MapMask kAllMaps = ~MapMask{0};

/// Applies the configured operator set to one retina level (paper Section 3: "it applies any
/// required convolution operators over this MR"). Separable masks run as a row pass over the
/// level's rows plus apron and a column pass over the interior; masks sharing a row factor
/// share its pass. Not thread-safe (owns scratch); one bank per thread.
class OperatorBank {
 public:
  /// Builds every mask. Throws std::invalid_argument on an invalid config (the loader checks
  /// the same rules with file positions).
  OperatorBank(const OperatorConfig& config, int width, int height);

  const std::vector<MapSpec>& maps() const { return specs_; }
  int map_count() const { return static_cast<int>(specs_.size()); }
  /// Index of a named map, or -1.
  int find(std::string_view name) const;
  /// The largest half-width of any mask: the retina apron this bank needs.
  int apron_px() const { return apron_; }

  /// Computes the requested maps of `level` into `out`, map i at out + i * width * height
  /// (rows of `width` floats). Maps not requested are left untouched. Real-time safe.
  void apply(const RetinaLevelView& level, MapMask request, float* out) const noexcept;

 private:
  struct GaussianFamily {
    double sigma_px = 0.0;
    int half_width = 0;
    Taps order0;                      ///< lambda e^(a t^2)
    Taps order1;                      ///< 2 a lambda e^(a t^2) t
    Taps order2;                      ///< 2 a lambda e^(a t^2) (2 a t^2 + 1)
    Taps across;                      ///< e^(a t^2), the unnormalised factor across d in Eq. 4-5
    float order0_over_across = 1.0f;  ///< lambda: order0 = lambda * across.
    int first_map = 0;                ///< g0x, g0y, g1x, g1y, g2x, g2y follow in that order.
    int laplacian_map = -1;
  };
  struct Mask {
    int map = 0;
    bool separable = false;
    Taps row;
    Taps column;
    int rows = 0;
    int cols = 0;
    std::vector<float> values;
  };
  float* map_out(float* out, int index) const {
    return out + static_cast<std::ptrdiff_t>(index) * width_ * height_;
  }
  void apply_separable(const RetinaLevelView& level, const Taps& row, const Taps& column,
                       float* out) const noexcept;

  int width_ = 0;
  int height_ = 0;
  int apron_ = 0;
  std::vector<MapSpec> specs_;
  std::vector<GaussianFamily> gaussians_;
  int sobel_map_ = -1;
  Taps sobel_derivative_;
  Taps sobel_smooth_;
  int average_map_ = -1;
  Taps box_;
  std::vector<Mask> masks_;
  mutable std::vector<float>
      scratch_;  ///< Row-pass results: 3 planes of width x (height + 2 apron).
};

}  // namespace cambio::perception
