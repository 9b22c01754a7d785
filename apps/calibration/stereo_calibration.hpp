#pragma once

#include <array>
#include <string>
#include <vector>

#include <Eigen/Geometry>
#include <opencv2/core.hpp>

#include "cambio/hal/camera.hpp"
#include "chessboard.hpp"

namespace cambio::app {

/// One camera's pinhole intrinsics and plumb-bob distortion, as the HAL's CameraInfo holds them.
struct CameraCalibration {
  int width_px = 0;
  int height_px = 0;
  double focal_x_px = 0.0;
  double focal_y_px = 0.0;
  double principal_x_px = 0.0;  ///< From the top-left pixel's centre.
  double principal_y_px = 0.0;
  hal::PlumbBobDistortion distortion;
  double mono_rms_px = 0.0;  ///< Reprojection RMS of this camera's calibration alone.

  /// The 3x3 camera matrix, row-major (ROS's camera_matrix.data).
  std::array<double, 9> camera_matrix() const;
};

/// A board found in both images of one view.
struct StereoView {
  std::string view_id;
  std::vector<cv::Point2f> left_px;
  std::vector<cv::Point2f> right_px;
};

/// A view's reprojection RMS after the stereo fit.
struct ViewError {
  std::string view_id;
  double left_rms_px = 0.0;
  double right_rms_px = 0.0;
  double rms_px = 0.0;  ///< Both images' points together.
};

/// stereoRectify's output in ROS camera_info's terms: R rotates a camera's frame into the common
/// rectified frame; P projects rectified points (the right's P holds Tx = -fx' * baseline).
struct StereoRectification {
  std::array<double, 9> R_left{};  ///< Row-major.
  std::array<double, 9> R_right{};
  std::array<double, 12> P_left{};  ///< Row-major 3x4.
  std::array<double, 12> P_right{};
};

struct StereoCalibration {
  CameraCalibration left;
  CameraCalibration right;
  /// The right camera's optical frame in the left's (OpenCV's: z forward, x right, y down), in
  /// metres: p_L = X_LR * p_R.
  Eigen::Isometry3d X_LR = Eigen::Isometry3d::Identity();
  std::vector<ViewError> views;  ///< In the order given.
  double rms_px = 0.0;           ///< Over every point of both cameras (stereoCalibrate's).
  StereoRectification rectification;
};

/// Calibrates each camera (calibrateCamera: focal lengths, principal point, k1 k2 p1 p2 k3), then
/// both together with their relative pose (stereoCalibrate, the intrinsics refined), and
/// rectifies the pair (stereoRectify, zero disparity at infinity, alpha 0: only valid pixels).
/// `views` must hold at least three views (Zhang's minimum for a planar target); the command asks
/// for more. Images are `width_px` x `height_px`.
StereoCalibration calibrate_stereo(const std::vector<StereoView>& views,
                                   const ChessboardSpec& board, int width_px, int height_px);

}  // namespace cambio::app
