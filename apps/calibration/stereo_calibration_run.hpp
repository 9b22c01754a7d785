#pragma once

#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <ostream>

#include "calibration_files.hpp"
#include "cambio/config/rig_config.hpp"
#include "chessboard.hpp"
#include "output_directory.hpp"

namespace cambio::app {

/// The fewest views with the board in both images that a stereo calibration accepts. Zhang's
/// method needs 3 views of a plane for the intrinsics alone; each camera here fits 9 intrinsic
/// parameters and the pair 6 more, and OpenCV's tutorial asks for 10 or more. Below 6 the fit
/// reaches a low RMS on a wrong answer (distortion absorbing the pose), so it is refused.
inline constexpr std::size_t kMinStereoViews = 6;

/// Besides kRigCalibrationFileName, one ROS camera_info file per camera is written, named
/// `<camera>.yaml` as camera_info_manager expects.

struct StereoCalibrationInputs {
  std::filesystem::path images_dir;
  ChessboardSpec board;
  config::RigConfig rig;  ///< Must have a stereo section; its cameras give names and sizes.
  CalibrationProvenance provenance;
};

enum class StereoCalibrationOutcome : std::uint8_t {
  kCalibrated,   ///< Files committed to the output directory.
  kTooFewViews,  ///< Fewer than kMinStereoViews views had the board in both images.
};

/// `cambio calibrate stereo`'s work: pairs the images (find_stereo_image_pairs), finds the board
/// in each, names every view refused and why, calibrates (calibrate_stereo), prints the RMS per
/// view and overall and the fitted values to `report`, and commits the rig's calibration file and
/// the two camera_info files to `out`. Throws CalibrationInputError for images that cannot be
/// paired or read or whose size is not the rig camera's, and OutputError.
StereoCalibrationOutcome run_stereo_calibration(const StereoCalibrationInputs& inputs,
                                                OutputDirectory& out, std::ostream& report);

}  // namespace cambio::app
