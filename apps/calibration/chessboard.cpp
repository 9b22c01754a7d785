#include "chessboard.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include <opencv2/calib3d.hpp>
#include <opencv2/imgproc.hpp>

#include "image_files.hpp"
#include "stereo_image_pairs.hpp"

namespace cambio::app {

namespace {

/// The shortest distance between neighbouring corners, in pixels.
double corner_spacing_px(const std::vector<cv::Point2f>& corners, const ChessboardSpec& board) {
  double spacing = std::numeric_limits<double>::infinity();
  for (int row = 0; row < board.inner_rows; ++row) {
    for (int column = 0; column < board.inner_columns; ++column) {
      const cv::Point2f& corner =
          corners[static_cast<std::size_t>(row * board.inner_columns + column)];
      if (column + 1 < board.inner_columns) {
        spacing = std::min(
            spacing,
            cv::norm(corner -
                     corners[static_cast<std::size_t>(row * board.inner_columns + column + 1)]));
      }
      if (row + 1 < board.inner_rows) {
        spacing = std::min(
            spacing,
            cv::norm(corner -
                     corners[static_cast<std::size_t>((row + 1) * board.inner_columns + column)]));
      }
    }
  }
  return spacing;
}

}  // namespace

std::vector<cv::Point3f> board_corners_m(const ChessboardSpec& board) {
  std::vector<cv::Point3f> corners;
  for (int row = 0; row < board.inner_rows; ++row) {
    for (int column = 0; column < board.inner_columns; ++column) {
      corners.emplace_back(static_cast<float>(column * board.square_m),
                           static_cast<float>(row * board.square_m), 0.0F);
    }
  }
  return corners;
}

std::optional<std::vector<cv::Point2f>> find_board_corners_px(const cv::Mat& grey,
                                                              const ChessboardSpec& board) {
  std::vector<cv::Point2f> corners;
  const int flags = cv::CALIB_CB_ADAPTIVE_THRESH | cv::CALIB_CB_NORMALIZE_IMAGE;
  if (!cv::findChessboardCorners(grey, board.pattern_size(), corners, flags)) return std::nullopt;
  // cornerSubPix's window must stay inside one square: a window that reaches the next corner
  // pulls the estimate toward it. OpenCV's sample uses 11 (a 23 px window) on boards whose
  // squares are ~30 px; smaller boards get a proportionally smaller window.
  const double spacing_px = corner_spacing_px(corners, board);
  const int half_window_px = std::clamp(static_cast<int>(std::floor(0.4 * spacing_px)), 2, 11);
  cv::cornerSubPix(grey, corners, cv::Size(half_window_px, half_window_px), cv::Size(-1, -1),
                   cv::TermCriteria(cv::TermCriteria::COUNT | cv::TermCriteria::EPS, 50, 1e-4));
  return corners;
}

cv::Mat read_calibration_image(const std::filesystem::path& path,
                               const config::CameraConfig& camera, const std::string& option) {
  hal::Image image;
  try {
    image = read_image_file(path.string(), hal::PixelFormat::kGrey8);
  } catch (const ImageFileError& error) {
    throw CalibrationInputError(option + ": " + error.what());
  }
  const cv::Mat grey =
      cv::Mat(image.height_px, image.width_px, CV_8UC1, image.pixels.data()).clone();
  if (grey.cols != camera.width_px || grey.rows != camera.height_px) {
    throw CalibrationInputError(option + ": '" + path.string() + "' is " +
                                std::to_string(grey.cols) + "x" + std::to_string(grey.rows) +
                                " px, expected the rig's " + std::to_string(camera.width_px) + "x" +
                                std::to_string(camera.height_px) + " of camera '" + camera.name +
                                "' (a calibration holds for one resolution)");
  }
  return grey;
}

}  // namespace cambio::app
