#include "stereo_calibration.hpp"

#include <cmath>
#include <stdexcept>

#include <opencv2/calib3d.hpp>

namespace cambio::app {

namespace {

const cv::TermCriteria kCriteria(cv::TermCriteria::COUNT | cv::TermCriteria::EPS, 200, 1e-9);

CameraCalibration from_opencv(const cv::Mat& K, const cv::Mat& D, int width_px, int height_px) {
  CameraCalibration camera;
  camera.width_px = width_px;
  camera.height_px = height_px;
  camera.focal_x_px = K.at<double>(0, 0);
  camera.focal_y_px = K.at<double>(1, 1);
  camera.principal_x_px = K.at<double>(0, 2);
  camera.principal_y_px = K.at<double>(1, 2);
  const auto* d = D.ptr<double>();
  camera.distortion = {d[0], d[1], d[2], d[3], d[4]};
  return camera;
}

template <std::size_t N>
std::array<double, N> row_major(const cv::Mat& matrix) {
  cv::Mat as_double;
  matrix.convertTo(as_double, CV_64F);
  if (as_double.total() != N) throw std::logic_error("calibration: unexpected matrix size");
  std::array<double, N> values{};
  for (std::size_t i = 0; i < N; ++i) values[i] = as_double.ptr<double>()[i];
  return values;
}

}  // namespace

std::array<double, 9> CameraCalibration::camera_matrix() const {
  return {focal_x_px, 0.0, principal_x_px, 0.0, focal_y_px, principal_y_px, 0.0, 0.0, 1.0};
}

StereoCalibration calibrate_stereo(const std::vector<StereoView>& views,
                                   const ChessboardSpec& board, int width_px, int height_px) {
  if (views.size() < 3) throw std::invalid_argument("calibrate_stereo: fewer than 3 views");
  const cv::Size size(width_px, height_px);
  const std::vector<std::vector<cv::Point3f>> board_m(views.size(), board_corners_m(board));
  std::vector<std::vector<cv::Point2f>> left_px;
  std::vector<std::vector<cv::Point2f>> right_px;
  for (const auto& view : views) {
    left_px.push_back(view.left_px);
    right_px.push_back(view.right_px);
  }

  // Each camera alone first: stereoCalibrate refines from these (USE_INTRINSIC_GUESS) instead
  // of fitting 2 x 9 intrinsics and the pose at once from a poor start.
  cv::Mat K_left;
  cv::Mat D_left;
  cv::Mat K_right;
  cv::Mat D_right;
  std::vector<cv::Mat> rvecs;
  std::vector<cv::Mat> tvecs;
  const double left_rms_px =
      cv::calibrateCamera(board_m, left_px, size, K_left, D_left, rvecs, tvecs, 0, kCriteria);
  const double right_rms_px =
      cv::calibrateCamera(board_m, right_px, size, K_right, D_right, rvecs, tvecs, 0, kCriteria);

  cv::Mat R_RL;
  cv::Mat t_RL;
  cv::Mat E;
  cv::Mat F;
  cv::Mat per_view_rms_px;
  StereoCalibration result;
  result.rms_px =
      cv::stereoCalibrate(board_m, left_px, right_px, K_left, D_left, K_right, D_right, size, R_RL,
                          t_RL, E, F, per_view_rms_px, cv::CALIB_USE_INTRINSIC_GUESS, kCriteria);
  result.left = from_opencv(K_left, D_left, width_px, height_px);
  result.left.mono_rms_px = left_rms_px;
  result.right = from_opencv(K_right, D_right, width_px, height_px);
  result.right.mono_rms_px = right_rms_px;

  // OpenCV's R, T map left-camera points into the right camera (p_R = R p_L + T): X_RL.
  Eigen::Isometry3d X_RL = Eigen::Isometry3d::Identity();
  for (int r = 0; r < 3; ++r) {
    for (int c = 0; c < 3; ++c) X_RL.linear()(r, c) = R_RL.at<double>(r, c);
    X_RL.translation()(r) = t_RL.at<double>(r);
  }
  result.X_LR = X_RL.inverse();

  for (std::size_t v = 0; v < views.size(); ++v) {
    const double l = per_view_rms_px.at<double>(static_cast<int>(v), 0);
    const double r = per_view_rms_px.at<double>(static_cast<int>(v), 1);
    // Both images hold the same number of corners, so the pooled RMS is the RMS of the two.
    result.views.push_back({views[v].view_id, l, r, std::sqrt((l * l + r * r) / 2.0)});
  }

  cv::Mat R_left;
  cv::Mat R_right;
  cv::Mat P_left;
  cv::Mat P_right;
  cv::Mat Q;
  cv::stereoRectify(K_left, D_left, K_right, D_right, size, R_RL, t_RL, R_left, R_right, P_left,
                    P_right, Q, cv::CALIB_ZERO_DISPARITY, 0.0);
  result.rectification = {row_major<9>(R_left), row_major<9>(R_right), row_major<12>(P_left),
                          row_major<12>(P_right)};
  return result;
}

}  // namespace cambio::app
