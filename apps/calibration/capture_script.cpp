#include "capture_script.hpp"

#include <cmath>
#include <numbers>
#include <sstream>

#include <yaml-cpp/yaml.h>

#include "stereo_image_pairs.hpp"

namespace cambio::app {

namespace {

constexpr double kDegPerRad = 180.0 / std::numbers::pi;

std::string number(double value) {
  std::ostringstream out;
  out.precision(10);
  out << value;
  return out.str();
}

}  // namespace

std::vector<CapturePose> read_capture_poses(const std::filesystem::path& path,
                                            const config::RigConfig& rig) {
  const std::string where = "--poses: " + path.string();
  YAML::Node root;
  try {
    root = YAML::LoadFile(path.string());
  } catch (const YAML::Exception& error) {
    throw CalibrationInputError(where + ": " + error.what());
  }
  const YAML::Node list = root["poses"];
  if (!list || !list.IsSequence() || list.size() == 0) {
    throw CalibrationInputError(
        where + ": expected a poses list of maps (joint name: degrees), found none");
  }
  std::vector<CapturePose> poses;
  for (std::size_t i = 0; i < list.size(); ++i) {
    const std::string at = where + ": pose " + std::to_string(i + 1);
    if (!list[i].IsMap() || list[i].size() == 0) {
      throw CalibrationInputError(at + ": expected a map of joint name: degrees");
    }
    CapturePose pose;
    for (const auto& entry : list[i]) {
      const std::string name = entry.first.as<std::string>();
      const config::JointConfig* joint = rig.find_joint(name);
      if (joint == nullptr) {
        throw CalibrationInputError(at + ": rig '" + rig.name + "' has no joint '" + name + "'");
      }
      double deg = NAN;
      try {
        deg = entry.second.as<double>();
      } catch (const YAML::Exception&) {
        deg = NAN;
      }
      const double rad = deg / kDegPerRad;
      if (!std::isfinite(rad) || rad < joint->min_position_rad || rad > joint->max_position_rad) {
        throw CalibrationInputError(at + ": " + name + ": expected degrees within its limits [" +
                                    number(joint->min_position_rad * kDegPerRad) + ", " +
                                    number(joint->max_position_rad * kDegPerRad) + "], found " +
                                    (entry.second.IsScalar() ? entry.second.as<std::string>()
                                                             : std::string("a non-number")));
      }
      pose[name] = rad;
    }
    poses.push_back(std::move(pose));
  }
  return poses;
}

std::vector<std::string> capture_script(const std::vector<CapturePose>& poses,
                                        const CapturePose& start, const config::RigConfig& rig,
                                        const std::string& camera,
                                        const std::filesystem::path& directory, double settle_s) {
  std::vector<std::string> lines{"verge off"};
  CapturePose at = start;
  for (const CapturePose& pose : poses) {
    for (const auto& [name, rad] : pose) {
      const config::JointConfig* joint = rig.find_joint(name);
      const auto from = at.find(name);
      const double distance = std::abs(rad - (from != at.end() ? from->second : 0.0));
      // One joint at a time: a move replaces the one before it on the gaze loop's channel.
      lines.push_back("move " + name + " " + number(rad));
      lines.push_back("wait " + number(distance / joint->max_velocity_rad_s + 0.05));
      at[name] = rad;
    }
    lines.push_back("wait " + number(settle_s));
    lines.push_back("capture " + camera + " " + directory.string());
  }
  lines.push_back("quit");
  return lines;
}

}  // namespace cambio::app
