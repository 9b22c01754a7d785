#pragma once

#include <array>
#include <optional>
#include <vector>

#include <Eigen/Geometry>
#include <opencv2/core.hpp>

#include "cambio/hal/camera.hpp"

namespace cambio::testing {

/// A camera with known truth: pinhole intrinsics and plumb-bob distortion, pixel centres at
/// integer coordinates (OpenCV's convention).
struct TrueCamera {
  int width_px = 640;
  int height_px = 480;
  double focal_x_px = 0.0;
  double focal_y_px = 0.0;
  double principal_x_px = 0.0;
  double principal_y_px = 0.0;
  hal::PlumbBobDistortion distortion;
};

/// The printed target: `inner_columns` x `inner_rows` inner corners of `square_m` squares, a white
/// margin of one square around the 10 x 7 (for 9x6) squares, on a mid-grey wall. The board frame
/// has its origin at the first inner corner, x along a row, y down the columns, z into the board,
/// as OpenCV's object points; the square at the origin's upper left is black.
struct TrueBoard {
  int inner_columns = 9;
  int inner_rows = 6;
  double square_m = 0.025;
};

/// The distortion model written out (Brown-Conrady as OpenCV and ROS define plumb_bob), applied
/// to normalised coordinates; kept here so the test's truth does not come from OpenCV.
Eigen::Vector2d distort(const hal::PlumbBobDistortion& d, const Eigen::Vector2d& undistorted);

/// Inverts distort() by Newton's method with a numerical Jacobian; nullopt when it does not
/// converge to 1e-12 (a point beyond the model's fold).
std::optional<Eigen::Vector2d> undistort(const hal::PlumbBobDistortion& d,
                                         const Eigen::Vector2d& distorted);

/// Where a point of the camera's frame (z forward) appears, in pixels; nullopt behind it.
std::optional<Eigen::Vector2d> project_px(const TrueCamera& camera, const Eigen::Vector3d& p_C);

/// Grey images of the board by inverse mapping: each of `samples_per_side`^2 sub-pixel samples of
/// a pixel is undistorted (once, at construction), cast as a ray onto the board's plane and given
/// the texture's exact grey there; a pixel is their mean (a box filter, as a sensor integrates
/// over its pixel's area).
class BoardRenderer {
 public:
  /// Throws std::runtime_error where the distortion does not invert inside the image.
  BoardRenderer(const TrueCamera& camera, int samples_per_side);
  /// The board at pose X_CB (board frame in camera frame).
  cv::Mat render(const TrueBoard& board, const Eigen::Isometry3d& X_CB) const;

 private:
  TrueCamera camera_;
  int samples_per_side_;
  std::vector<Eigen::Vector3d> rays_;  ///< (x, y, 1) per sample, pixel by pixel.
};

}  // namespace cambio::testing
