#pragma once

#include <cstddef>
#include <span>
#include <string>
#include <vector>

#include <Eigen/Geometry>

#include "cambio/hal/camera.hpp"

namespace cambio::app {

/// One view of a fixed chessboard by a camera on a moving link (eye-in-hand).
struct HandEyeView {
  std::string view_id;
  Eigen::Isometry3d X_BP = Eigen::Isometry3d::Identity();  ///< The camera's link in base (joints).
  Eigen::Isometry3d X_CT = Eigen::Isometry3d::Identity();  ///< The board in the camera (image).
  double pnp_rms_px = 0.0;                  ///< Reprojection RMS of the board's pose in this view.
  std::vector<Eigen::Vector2d> corners_px;  ///< The board's corners found in the image.
};

/// The board's corners in its own frame and the camera that saw them (pinhole and plumb-bob
/// distortion, pixel centres at integer coordinates).
struct HandEyeTarget {
  std::vector<Eigen::Vector3d> corners_T_m;
  double focal_x_px = 0.0;
  double focal_y_px = 0.0;
  double principal_x_px = 0.0;
  double principal_y_px = 0.0;
  hal::PlumbBobDistortion distortion;
};

/// The camera's mount and how well the views agree with it.
struct HandEyeCalibration {
  Eigen::Isometry3d X_PC = Eigen::Isometry3d::Identity();  ///< Optical frame in its link.
  /// The board in base as each view puts it through X_PC (X_BP X_PC X_CT), and their spread: the
  /// RMS distance of the views' board origins from their mean, and the RMS angle of their
  /// rotations from the fitted one. A fixed board gives zero up to the joints' and images' errors.
  std::vector<Eigen::Isometry3d> X_BT;
  double board_spread_m = 0.0;
  double board_spread_rad = 0.0;
  /// The corners' reprojection RMS over every view through the mount and one board pose.
  double reprojection_rms_px = 0.0;
};

/// The fewest views a hand-eye calibration accepts: 3 determine the mount when the motions
/// between them turn about two different axes; more average the joints' and images' noise.
inline constexpr std::size_t kMinHandEyeViews = 5;

/// Whether the motions between the views turn the link about at least two axes more than
/// `min_angle_rad` apart (the mount's rotation about a single axis of motion is not observable);
/// the largest angle found between two motions' axes.
double largest_motion_axis_angle_rad(std::span<const HandEyeView> views);

/// The mount X_PC from views of one fixed board: Park and Martin's solution of AX = XB
/// (OpenCV's calibrateHandEye), then refined with the board's pose in base by Levenberg-Marquardt
/// on the corners' reprojection error over every view (one board pose for all views: a single
/// view's pose of a board seen nearly square-on is weak in its tilt, the views together are not).
/// At least kMinHandEyeViews views; throws std::invalid_argument otherwise.
HandEyeCalibration calibrate_hand_eye(std::span<const HandEyeView> views,
                                      const HandEyeTarget& target);

}  // namespace cambio::app
