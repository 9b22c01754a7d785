#pragma once

#include <string>
#include <vector>

namespace cambio::config {
class MapReader;
struct ConfigOverride;
}  // namespace cambio::config

namespace cambio::perception {

/// The multi-resolution image (paper Section 3, Figure 1): `levels` images of width_px x
/// height_px; level k averages 2^k x 2^k blocks over a region 2^k times larger than level 0.
struct RetinaConfig {
  int levels = 4;
  int width_px = 16;
  int height_px = 16;
  /// Widen the coarsest level's blocks (beyond 2^(L-1)) so it covers the whole image around
  /// the fixation point, as in the paper's Figure 1.
  bool coarsest_covers_field = false;
};

/// A convolution mask given in config, applied as written (correlation: the value at row r,
/// column c weighs the pixel at offset (c - cols/2, r - rows/2)), like cv::filter2D.
struct UserMask {
  std::string name;
  int rows = 0;
  int cols = 0;
  std::vector<double> values;  ///< Row-major, rows * cols.
};

/// The operator set applied to every level of each eye's retina (paper Section 3, Eq. 1-5).
struct OperatorConfig {
  std::vector<double> sigmas_px{1.4, 2.7, 4.0};
  /// Half-width s of the Gaussian-derivative masks: s = ceil(half_width_sigmas * sigma) unless
  /// half_width_px > 0 fixes it for every sigma (the paper's example: sigma 1.7, s = 3).
  double half_width_sigmas = 3.0;
  int half_width_px = 0;
  bool laplacian_of_gaussian = true;
  bool sobel = true;
  int average_radius_px = 1;  ///< Box of (2r+1)^2; 0 disables it.
  std::vector<UserMask> masks;
};

/// Coarse-to-fine correlation of second-order Gaussian-derivative maps (paper Section 3).
struct DisparityConfig {
  bool enabled = true;
  std::vector<std::string> features{"g2x@1.4", "g2y@1.4"};
  double search_range_px = 32.0;  ///< +- range searched at the coarsest level, level-0 px.
  int window_half_px = 0;         ///< Correlation window half-size in level px; 0: width/4.
  int refine_range_px = 2;        ///< +- search around the coarser estimate, level px.
  double min_texture_rms = 0.5;   ///< Below this rms feature deviation a level is invalid.
  /// +- level-0 px of the whole-range scan (DisparityScan); 0: no scan. A run sets it from the
  /// rig when the file leaves it out (the largest disparity a target at the nearest supported
  /// fixation distance can have).
  double scan_range_px = 0.0;
  /// The scan takes the finest retina level whose correlation window spans this many px.
  double scan_window_px = 32.0;
};

/// The nearest fixation distance the stack supports (m): nearer, the eyes' pans and the arms'
/// reach end anyway.
inline constexpr double kNearestFixation_m = 0.3;

/// The largest disparity (level-0 px, either sign) a rig with this focal length and baseline can
/// see at the retina's centre: a target at kNearestFixation_m with the eyes parallel
/// (f b / z), or the eyes verged on it and the fixation moved to infinity.
inline double largest_disparity_px(double focal_px, double baseline_m) {
  return focal_px * baseline_m / kNearestFixation_m;
}

/// Lucas-Kanade translation per level from two consecutive frames of one eye.
struct MotionConfig {
  bool enabled = true;
  double sigma_px = 1.4;
  int iterations = 4;
  double min_eigenvalue = 1e-3;  ///< Smallest structure-tensor eigenvalue (per pixel) to trust.
  /// The key frame (what the displacement since a held frame is measured from) is renewed when
  /// its content has moved more than this (level-0 px) or is this many frames old.
  double rekey_shift_px = 6.0;
  int rekey_frames = 15;
};

/// Statistical moments of a map (default: the retina intensity), per level.
struct MomentsConfig {
  enum class Mode { kWeighted, kAbove, kBelow };
  bool enabled = true;
  std::string map = "intensity";
  Mode mode = Mode::kAbove;
  double threshold = 128.0;
};

/// The fixated object's region (ZeroDisparityFilter), computed only when a consumer asks for it
/// (pursuit does).
struct FixatedRegionConfig {
  bool enabled = true;
  int cell_px = 8;           ///< Side of a cell, image px.
  int cells = 32;            ///< Cells per side of the searched window, centred on the fixation.
  int max_disparity_px = 2;  ///< Shifts tried either way: a fixated surface's own relief.
  double min_correlation = 0.8;
  double min_texture_grey = 3.0;  ///< A cell's grey-level standard deviation below this is flat.
  int seed_radius_cells = 2;      ///< How far from the fixation the region's first cell may be.
  int min_cells = 4;
};

/// Everything the Sensory Servo Module needs; const after load.
struct SsmConfig {
  double rate_hz = 30.0;
  RetinaConfig retina;
  OperatorConfig operators;
  DisparityConfig disparity;
  MotionConfig motion;
  MomentsConfig moments;
  FixatedRegionConfig region;
};

/// Reads an SSM config map (the root of firmware_config/perception/ssm.yaml). Missing keys take
/// the defaults above; issues are recorded in the reader's IssueList.
SsmConfig read_ssm_config(config::MapReader& root);

/// Loads and validates a file; throws config::ConfigError listing every issue.
SsmConfig load_ssm_config(const std::string& path,
                          const std::vector<config::ConfigOverride>& overrides);

/// The shipped defaults file, perception/ssm.yaml (see config::find_shipped_config). Throws
/// config::ConfigError naming where it looked when there is none.
std::string default_ssm_config_path();

}  // namespace cambio::perception
