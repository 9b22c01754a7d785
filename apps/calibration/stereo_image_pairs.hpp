#pragma once

#include <filesystem>
#include <stdexcept>
#include <string>
#include <vector>

namespace cambio::app {

/// A problem with the calibration's inputs (the image folder, an image); the message names the
/// files. Commands exit 2 on it.
class CalibrationInputError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

/// Whether `extension` (with its dot, any case) is one of kCalibrationImageExtensions.
bool is_calibration_image_extension(std::string extension);

/// One stereo view: `left<ID>.<ext>` with `right<ID>.<ext>` (OpenCV's samples' naming:
/// left01.jpg with right01.jpg). The two may differ in extension.
struct StereoImagePair {
  std::string view_id;  ///< The shared ID, e.g. "01".
  std::filesystem::path left;
  std::filesystem::path right;
};

/// The image extensions a view is looked for under (lower or upper case).
inline constexpr const char* kCalibrationImageExtensions =
    "png, jpg, jpeg, pgm, ppm, bmp, tif, tiff";

/// The views in `directory`, by ID. Only image files whose names start with "left" or "right"
/// take part; other files are left alone. Throws CalibrationInputError naming every image without
/// its partner and every ID given twice on one side (left01.png and left01.jpg), or when the
/// folder cannot be read or holds no pair.
std::vector<StereoImagePair> find_stereo_image_pairs(const std::filesystem::path& directory);

}  // namespace cambio::app
