#include "rig_backend_check.hpp"

#include <vector>

#include "cambio/config/hardware_description.hpp"

namespace cambio::app {

void check_rig_backends(const config::RigConfig& rig, const hal::BackendFactory& factory) {
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
  for (auto& problem : factory.check(config::hardware_description(rig))) {
    issues.push_back(rig.locate(problem.key_path, std::move(problem.message)));
  }
  if (!issues.empty()) throw config::ConfigError(std::move(issues));
}

}  // namespace cambio::app
