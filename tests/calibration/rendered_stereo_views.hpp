#pragma once

#include <filesystem>
#include <vector>

#include <Eigen/Geometry>

#include "chessboard_renderer.hpp"

namespace cambio::testing {

/// A stereo pair with known truth, as the rendered calibration tests use it: two cameras with
/// different intrinsics and distortion, the right one 0.12 m to the left one's right (x), slightly
/// off the line and rotated.
struct TrueStereoPair {
  TrueCamera left;
  TrueCamera right;
  Eigen::Isometry3d X_LR = Eigen::Isometry3d::Identity();  ///< Right camera in the left's frame.
};

TrueStereoPair true_stereo_pair();

/// Board poses X_LB (board in the left camera) seen whole by both cameras with a 10 px margin,
/// 0.5 to 0.85 m away, tilted up to 30 deg each way and spun up to 15 deg (deterministic).
std::vector<Eigen::Isometry3d> board_poses(const TrueStereoPair& pair, const TrueBoard& board,
                                           int count);

/// Renders the views into `directory` as left01.png / right01.png, ... (3 x 3 samples a pixel).
void write_rendered_views(const TrueStereoPair& pair, const TrueBoard& board,
                          const std::vector<Eigen::Isometry3d>& poses,
                          const std::filesystem::path& directory);

}  // namespace cambio::testing
