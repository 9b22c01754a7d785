#pragma once

#include <filesystem>
#include <map>
#include <string>
#include <vector>

#include "cambio/config/rig_config.hpp"

namespace cambio::app {

/// One head pose of a capture: joint name -> angle (rad).
using CapturePose = std::map<std::string, double>;

/// The poses of a `calibrate capture` file, in degrees as people write them:
///
///     poses:
///       - {neck_pan: 10, neck_tilt: -5, eye_tilt: 4, left_eye_pan: 3}
///       - {neck_pan: -8, neck_tilt: 6, eye_tilt: -2, left_eye_pan: -4}
///
/// Throws CalibrationInputError naming the file, the pose (1-based) and the joint for a file that
/// cannot be read or parsed, no poses, a joint the rig does not have, or an angle that is not
/// finite or beyond the joint's limits.
std::vector<CapturePose> read_capture_poses(const std::filesystem::path& path,
                                            const config::RigConfig& rig);

/// The console lines that take the views: vergence off (the other eye must not move on its
/// own), then for each pose each joint moved in turn with time to get there at its velocity
/// limit from where it was, `settle_s` more, and `capture CAMERA DIR`; `start` is where the
/// joints are before the first pose (the experiment's initial pose).
std::vector<std::string> capture_script(const std::vector<CapturePose>& poses,
                                        const CapturePose& start, const config::RigConfig& rig,
                                        const std::string& camera,
                                        const std::filesystem::path& directory, double settle_s);

}  // namespace cambio::app
