// The experiment's `behaviour:` section.
#include "experiment_sections.hpp"
#include "format.hpp"

namespace cambio::config {

BehaviourConfig read_behaviour(MapReader behaviour,
                               const std::function<std::string(const std::string&)>& resolve) {
  BehaviourConfig config;
  config.name = behaviour.text("name");
  // Decisions take a frame or more to mean anything; faster than the control loop they could
  // not be carried out anyway.
  config.rate_hz = behaviour.number_or(
      "rate_hz", config.rate_hz,
      Range{0.0, 1000.0, true, false}.because("a behaviour runs no faster than the control loop"));
  const std::vector<std::string> plugins = behaviour.strings_or("plugins", {});
  for (std::size_t i = 0; i < plugins.size(); ++i) {
    if (plugins[i].empty()) {
      behaviour.error("plugins", i, "expected a shared library's path, found ''");
      continue;
    }
    const std::string path = resolve(plugins[i]);
    if (const auto problem = readable_file_problem(path)) {
      std::string message = "expected a readable shared library, found " + in_quotes(plugins[i]);
      if (path != plugins[i]) message += " (resolved to " + in_quotes(path) + ")";
      behaviour.error("plugins", i, message + ": " + *problem);
      continue;
    }
    config.plugins.push_back(path);
  }
  if (auto params = behaviour.optional_map("params")) {
    for (auto& entry : params->scalars()) {
      config.params.push_back({std::move(entry.key), std::move(entry.text),
                               params->file() + ":" + std::to_string(entry.line)});
    }
    params->finish();
  }
  behaviour.finish();
  return config;
}

}  // namespace cambio::config
