#pragma once

#include <filesystem>
#include <optional>
#include <vector>

#include <opencv2/core.hpp>

#include "cambio/config/rig_config.hpp"

namespace cambio::app {

/// A planar chessboard target, counted by its inner corners (OpenCV's convention: a 9x6 board
/// has 10 x 7 squares).
struct ChessboardSpec {
  int inner_columns = 0;
  int inner_rows = 0;
  double square_m = 0.0;  ///< Side of one square.

  cv::Size pattern_size() const { return {inner_columns, inner_rows}; }
};

/// The inner corners in the board's frame (z = 0, x along a row, y down the columns), in the
/// order findChessboardCorners reports them, in metres.
std::vector<cv::Point3f> board_corners_m(const ChessboardSpec& board);

/// The board's inner corners in `grey` (8-bit, one channel) refined to sub-pixel accuracy, in
/// pixels (origin at the top-left pixel's centre); nullopt when the whole board is not found.
std::optional<std::vector<cv::Point2f>> find_board_corners_px(const cv::Mat& grey,
                                                              const ChessboardSpec& board);

/// A calibration image as grey levels (8-bit, one channel). Throws CalibrationInputError, its
/// message starting with `option` (the command's option that named the folder), for an image
/// that cannot be read or is not `camera`'s size.
cv::Mat read_calibration_image(const std::filesystem::path& path,
                               const config::CameraConfig& camera, const std::string& option);

}  // namespace cambio::app
