#include "cambio/config/rig_config.hpp"

#include <algorithm>

namespace cambio::config {

namespace {

template <typename Item>
const Item* find_named(const std::vector<Item>& items, const std::string& name) {
  const auto it =
      std::find_if(items.begin(), items.end(), [&](const Item& item) { return item.name == name; });
  return it == items.end() ? nullptr : &*it;
}

}  // namespace

bool SimFoveationConfig::fits(int width_px, int height_px) const {
  if (periphery_downscale == 1) return true;
  const int s = periphery_downscale;
  const int f = fovea_px;
  return s >= 1 && width_px % s == 0 && height_px % s == 0 && f >= 1 &&
         f <= std::min(width_px, height_px) && (width_px - f) % 2 == 0 && (height_px - f) % 2 == 0;
}

const JointConfig* RigConfig::find_joint(const std::string& joint_name) const {
  return find_named(joints, joint_name);
}

const JointGroupConfig* RigConfig::find_group(const std::string& group_name) const {
  return find_named(groups, group_name);
}

const CameraConfig* RigConfig::find_camera(const std::string& camera_name) const {
  return find_named(cameras, camera_name);
}

const LoopConfig* RigConfig::find_loop(const std::string& loop_name) const {
  return find_named(loops, loop_name);
}

const CanBusConfig* RigConfig::find_can_bus(const std::string& bus_name) const {
  return find_named(can_buses, bus_name);
}

ConfigIssue RigConfig::locate(std::string_view key_path, std::string message) const {
  std::string_view path = key_path;
  ConfigIssue issue{source_file, 0, 0, {}, {}};
  while (!path.empty()) {
    if (const auto it = locations.find(path); it != locations.end()) {
      issue = it->second;
      break;
    }
    const auto dot = path.rfind('.');
    path = dot == std::string_view::npos ? std::string_view{} : path.substr(0, dot);
  }
  issue.key_path = std::string(key_path);
  issue.message = std::move(message);
  return issue;
}

}  // namespace cambio::config
