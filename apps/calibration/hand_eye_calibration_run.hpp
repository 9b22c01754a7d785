#pragma once

#include <cstdint>
#include <filesystem>
#include <ostream>
#include <string>

#include "calibration_files.hpp"
#include "cambio/config/rig_config.hpp"
#include "chessboard.hpp"
#include "output_directory.hpp"

namespace cambio::app {

struct HandEyeCalibrationInputs {
  std::filesystem::path views_dir;
  ChessboardSpec board;
  config::RigConfig rig;  ///< Its kinematics place the camera's link; its intrinsics are used.
  std::string camera;     ///< The camera whose mount is measured (on a moving link).
  CalibrationProvenance provenance;
};

enum class HandEyeCalibrationOutcome : std::uint8_t {
  kCalibrated,        ///< The calibration file committed to the output directory.
  kTooFewViews,       ///< Fewer than kMinHandEyeViews views had the whole board.
  kDegenerateMotion,  ///< The views turn the camera about one axis only.
};

/// `cambio calibrate hand-eye`'s work: finds the views (find_hand_eye_views), the board in each
/// (its pose from the camera's intrinsics and distortion as the rig has them), the camera's link
/// from the joint readings through the rig's kinematics, names every view refused and why,
/// calibrates (calibrate_hand_eye), prints each view's reprojection RMS, the mount and how well
/// the views agree on the board's place, and commits the rig's camera calibration file with the
/// new mount to `out`. Throws CalibrationInputError for a camera the rig does not have or that is
/// fixed to the base, images that cannot be read or are not the camera's size, readings that
/// cannot be read or miss a joint of the camera's chain; OutputError.
HandEyeCalibrationOutcome run_hand_eye_calibration(const HandEyeCalibrationInputs& inputs,
                                                   OutputDirectory& out, std::ostream& report);

}  // namespace cambio::app
