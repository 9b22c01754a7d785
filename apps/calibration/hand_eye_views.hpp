#pragma once

#include <filesystem>
#include <map>
#include <string>
#include <vector>

namespace cambio::app {

/// One hand-eye view: the camera's image `view<ID>.<ext>` and the joints' readings when it was
/// taken, `view<ID>.yaml` (what `cambio calibrate capture` writes):
///
///     joints_rad: {neck_pan: 0.1745, neck_tilt: -0.0873, eye_tilt: 0.0, left_eye_pan: 0.05}
struct HandEyeViewFiles {
  std::string view_id;  ///< e.g. "01".
  std::filesystem::path image;
  std::filesystem::path joints;
};

/// The views in `directory`, by ID. Throws CalibrationInputError naming every image without its
/// readings and every readings file without its image, or when the folder cannot be read or
/// holds no view.
std::vector<HandEyeViewFiles> find_hand_eye_views(const std::filesystem::path& directory);

/// The joint readings of a view's YAML file (joint name -> rad). Throws CalibrationInputError
/// naming the file (and line) for a file that cannot be read or parsed, no joints_rad map, or a
/// reading that is not a finite number.
std::map<std::string, double> read_joint_readings(const std::filesystem::path& path);

}  // namespace cambio::app
