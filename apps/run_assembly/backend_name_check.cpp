#include "backend_name_check.hpp"

#include <vector>

namespace cambio::app {

void check_backend_names(const config::RigConfig& rig, const hal::BackendFactory& factory) {
  std::vector<config::ConfigIssue> issues;
  const auto check = [&](const std::string& backend, config::ConfigIssue at) {
    std::string why = factory.unavailable_reason(backend);
    if (why.empty()) return;
    at.message = "backend '" + backend + "' " + std::move(why);
    issues.push_back(std::move(at));
  };
  for (const auto& group : rig.groups) check(group.backend, group.backend_at);
  for (const auto& camera : rig.cameras) check(camera.backend, camera.backend_at);
  for (const auto& sensor : rig.touch_sensors) check(sensor.backend, sensor.backend_at);
  if (!issues.empty()) throw config::ConfigError(std::move(issues));
}

}  // namespace cambio::app
