#pragma once

#include <string>

#include "cambio/config/rig_config.hpp"
#include "stereo_calibration.hpp"

namespace cambio::app {

/// The rig's camera calibration file, as the calibrate commands name it in their output folder.
inline constexpr const char* kRigCalibrationFileName = "camera_calibration.yaml";

/// Where a calibration came from, for the files' header comments.
struct CalibrationProvenance {
  std::string command_line;  ///< As the user could run it again.
  std::string board;         ///< e.g. "9x6 inner corners, 25 mm squares".
};

/// The rig's camera calibration file (config/camera_calibration.hpp): both cameras' size,
/// intrinsics and distortion, and the right camera's mount `right_mount` in its parent link, so
/// that a rig naming it under camera_calibration loads the calibrated values. The header comment
/// holds the provenance, the RMS and X_LR. Camera names are the rig's stereo pair's.
std::string rig_camera_calibration_yaml(const config::RigConfig& rig,
                                        const StereoCalibration& calibration,
                                        const config::Pose& right_mount,
                                        const CalibrationProvenance& provenance);

/// The rig's camera calibration file after a hand-eye calibration of `camera`: every camera of
/// the rig with its intrinsics, distortion and mount as loaded (the rig's own or its current
/// calibration file's), `camera`'s mount replaced by `mount`; the header comment holds the
/// provenance and `summary` (views, agreement).
std::string rig_camera_mount_yaml(const config::RigConfig& rig, const std::string& camera,
                                  const config::Pose& mount, const std::string& summary,
                                  const CalibrationProvenance& provenance);

/// One camera as a ROS camera_info YAML file (camera_calibration_parsers' format, as
/// camera_info_manager reads it): size, camera_name, camera_matrix, distortion_model plumb_bob
/// with k1 k2 p1 p2 k3, rectification_matrix and projection_matrix of the stereo rectification.
std::string ros_camera_info_yaml(const std::string& camera_name, const CameraCalibration& camera,
                                 const std::array<double, 9>& rectification,
                                 const std::array<double, 12>& projection);

}  // namespace cambio::app
