#pragma once

#include <string_view>

#include "cambio/config/map_reader.hpp"
#include "cambio/config/rig_config.hpp"
#include "cambio/hal/camera.hpp"

namespace cambio::config {

/// The rig key that names a camera calibration file, relative to the rig file's directory (or
/// absolute): `camera_calibration: calibration/cambio_cameras.yaml`. The file is what
/// `cambio calibrate stereo` writes, kept apart from the hand-written rig as ROS keeps
/// camera_info files apart from the URDF: it is regenerated at each calibration and read by
/// programs, while the rig file is edited by people and keeps their comments.
///
/// Its form, each camera's keys those of the rig's camera entry they replace:
///
///     cameras:
///       left_eye:
///         width_px: 640          # must equal the rig's: a calibration holds for one resolution
///         height_px: 480
///         focal_x_px: 600.2
///         focal_y_px: 600.9
///         principal_point_px: [321.4, 238.7]
///         distortion: {k1: -0.28, k2: 0.09, p1: 0.001, p2: -0.0004, k3: 0.0}
///       right_eye:
///         ...                    # as above, and its mount when the calibration measured it:
///         origin_xyz_m: [0.02, 0.0003, -0.0001]
///         origin_rpy_deg: [-90.1, 0.05, -89.8]
///
/// A camera the file names must be in the rig; one it does not name keeps the rig's values.
inline constexpr std::string_view kCameraCalibrationKey = "camera_calibration";

/// A `distortion: {k1, k2, p1, p2, k3}` map (OpenCV's plumb-bob model, all five required).
hal::PlumbBobDistortion read_plumb_bob_distortion(MapReader& distortion);

/// Reads the root's camera_calibration key, if present, and applies the file it names to the
/// rig's cameras (read after them). Issues in the calibration file are located in that file and
/// join the rig's issue list, so a rig and its calibration are checked in one pass.
void read_camera_calibration_key(MapReader& root, RigConfig& rig);

}  // namespace cambio::config
