#include "hand_eye_views.hpp"

#include <algorithm>
#include <cmath>
#include <system_error>

#include <yaml-cpp/yaml.h>

#include "stereo_image_pairs.hpp"

namespace cambio::app {

std::vector<HandEyeViewFiles> find_hand_eye_views(const std::filesystem::path& directory) {
  std::error_code error;
  if (!std::filesystem::is_directory(directory, error)) {
    throw CalibrationInputError("--views: '" + directory.string() + "' is not a directory");
  }
  std::map<std::string, std::vector<std::filesystem::path>> images;
  std::map<std::string, std::filesystem::path> readings;
  std::filesystem::directory_iterator it(directory, error);
  if (error) {
    throw CalibrationInputError("--views: cannot list '" + directory.string() +
                                "': " + error.message());
  }
  for (const auto& entry : it) {
    if (!entry.is_regular_file(error)) continue;
    const std::filesystem::path& path = entry.path();
    const std::string stem = path.stem().string();
    if (stem.size() <= 4 || !stem.starts_with("view")) continue;
    const std::string id = stem.substr(4);
    if (path.extension() == ".yaml") {
      readings[id] = path;
    } else if (is_calibration_image_extension(path.extension().string())) {
      images[id].push_back(path);
    }
  }
  std::vector<HandEyeViewFiles> views;
  std::string problems;
  const auto problem = [&](const std::string& text) {
    problems += (problems.empty() ? "" : "; ") + text;
  };
  for (auto& [id, paths] : images) {
    std::sort(paths.begin(), paths.end());
    if (paths.size() > 1) {
      problem(paths[0].filename().string() + " and " + paths[1].filename().string() +
              " are one view given twice");
    } else if (readings.count(id) == 0) {
      problem(paths[0].filename().string() + " has no view" + id + ".yaml (its joint readings)");
    } else {
      views.push_back({id, paths[0], readings[id]});
    }
  }
  for (const auto& [id, path] : readings) {
    if (images.count(id) == 0) problem(path.filename().string() + " has no image view" + id + ".*");
  }
  if (!problems.empty()) throw CalibrationInputError("--views: " + problems);
  if (views.empty()) {
    throw CalibrationInputError("--views: no view<ID>.<image> with view<ID>.yaml in '" +
                                directory.string() + "'");
  }
  return views;
}

std::map<std::string, double> read_joint_readings(const std::filesystem::path& path) {
  const std::string where = "--views: " + path.string();
  YAML::Node root;
  try {
    root = YAML::LoadFile(path.string());
  } catch (const YAML::Exception& error) {
    throw CalibrationInputError(where + ": " + error.what());
  }
  const YAML::Node joints = root["joints_rad"];
  if (!joints || !joints.IsMap()) {
    throw CalibrationInputError(where + ": expected a joints_rad map (joint name: radians)");
  }
  std::map<std::string, double> readings;
  for (const auto& entry : joints) {
    const std::string name = entry.first.as<std::string>();
    double value = NAN;
    try {
      value = entry.second.as<double>();
    } catch (const YAML::Exception&) {
      value = NAN;
    }
    if (!std::isfinite(value)) {
      throw CalibrationInputError(where + ":" + std::to_string(entry.second.Mark().line + 1) +
                                  ": joints_rad." + name + ": expected a finite number of radians");
    }
    readings[name] = value;
  }
  return readings;
}

}  // namespace cambio::app
