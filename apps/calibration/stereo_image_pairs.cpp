#include "stereo_image_pairs.hpp"

#include <algorithm>
#include <array>
#include <cctype>
#include <map>
#include <string_view>
#include <system_error>

namespace cambio::app {

bool is_calibration_image_extension(std::string extension) {
  std::transform(extension.begin(), extension.end(), extension.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  constexpr std::array<std::string_view, 8> kExtensions = {".png", ".jpg", ".jpeg", ".pgm",
                                                           ".ppm", ".bmp", ".tif",  ".tiff"};
  return std::find(kExtensions.begin(), kExtensions.end(), extension) != kExtensions.end();
}

namespace {

struct SideFiles {
  std::map<std::string, std::vector<std::filesystem::path>> by_id;
};

std::string names_of(const std::vector<std::filesystem::path>& paths) {
  std::string text;
  for (const auto& path : paths) text += (text.empty() ? "" : ", ") + path.filename().string();
  return text;
}

}  // namespace

std::vector<StereoImagePair> find_stereo_image_pairs(const std::filesystem::path& directory) {
  std::error_code error;
  if (!std::filesystem::is_directory(directory, error)) {
    throw CalibrationInputError("--images: '" + directory.string() + "' is not a directory");
  }
  SideFiles left;
  SideFiles right;
  std::filesystem::directory_iterator it(directory, error);
  if (error) {
    throw CalibrationInputError("--images: cannot list '" + directory.string() +
                                "': " + error.message());
  }
  for (const auto& entry : it) {
    if (!entry.is_regular_file(error)) continue;
    const std::filesystem::path& path = entry.path();
    if (!is_calibration_image_extension(path.extension().string())) continue;
    const std::string stem = path.stem().string();
    for (auto& [prefix, side] :
         {std::pair<std::string_view, SideFiles*>{"left", &left}, {"right", &right}}) {
      if (stem.size() > prefix.size() && stem.starts_with(prefix)) {
        side->by_id[stem.substr(prefix.size())].push_back(path);
      }
    }
  }

  // Directory order is the file system's: sort, so messages name files in one order.
  for (auto* side : {&left, &right}) {
    for (auto& [id, paths] : side->by_id) std::sort(paths.begin(), paths.end());
  }
  std::vector<StereoImagePair> pairs;
  std::vector<std::string> problems;
  for (const auto& [id, lefts] : left.by_id) {
    const auto partner = right.by_id.find(id);
    if (partner == right.by_id.end()) {
      problems.push_back(names_of(lefts) + " has no right" + id + ".*");
    } else if (lefts.size() == 1 && partner->second.size() == 1) {
      pairs.push_back({id, lefts.front(), partner->second.front()});
    }
  }
  for (const auto& [id, rights] : right.by_id) {
    if (left.by_id.count(id) == 0)
      problems.push_back(names_of(rights) + " has no left" + id + ".*");
  }
  for (const auto* side : {&left, &right}) {
    for (const auto& [id, paths] : side->by_id) {
      if (paths.size() > 1) problems.push_back(names_of(paths) + " are one view given twice");
    }
  }
  if (!problems.empty()) {
    std::string message = "--images: '" + directory.string() +
                          "' holds images that do not pair as leftID.* with rightID.*:";
    for (const auto& problem : problems) message += "\n  " + problem;
    throw CalibrationInputError(message);
  }
  if (pairs.empty()) {
    throw CalibrationInputError("--images: '" + directory.string() +
                                "' holds no image pair (expected leftID.* with rightID.*, e.g. "
                                "left01.png with right01.png; extensions " +
                                kCalibrationImageExtensions + ")");
  }
  // The map's order: IDs sorted as text, so left01..left14 keep their order.
  return pairs;
}

}  // namespace cambio::app
