#include "config_errors.hpp"

#include <iostream>

namespace cambio::app {

void report_config_error(const config::ConfigError& error) {
  for (const auto& issue : error.issues()) std::cerr << issue.to_string() << "\n";
  std::cerr << error.issues().size() << (error.issues().size() == 1 ? " problem" : " problems")
            << " found; nothing was started.\n";
}

std::optional<std::vector<config::ConfigOverride>> parse_overrides_or_report(
    const std::vector<std::string>& texts) {
  std::vector<config::ConfigOverride> overrides;
  std::vector<config::ConfigIssue> issues;
  for (const auto& text : texts) {
    try {
      overrides.push_back(config::parse_override(text));
    } catch (const config::ConfigError& error) {
      issues.insert(issues.end(), error.issues().begin(), error.issues().end());
    }
  }
  if (!issues.empty()) {
    report_config_error(config::ConfigError(std::move(issues)));
    return std::nullopt;
  }
  return overrides;
}

std::optional<config::RigConfig> load_rig_or_report(
    const std::string& path, const std::vector<config::ConfigOverride>& overrides) {
  try {
    return config::load_rig(path, overrides);
  } catch (const config::ConfigError& error) {
    report_config_error(error);
    return std::nullopt;
  }
}

std::optional<config::ExperimentConfig> load_experiment_or_report(
    const std::string& path, const std::vector<std::string>& set_texts) {
  const std::optional<std::vector<config::ConfigOverride>> overrides =
      parse_overrides_or_report(set_texts);
  if (!overrides) return std::nullopt;
  try {
    return config::load_experiment(path, *overrides);
  } catch (const config::ConfigError& error) {
    report_config_error(error);
    return std::nullopt;
  }
}

}  // namespace cambio::app
