#include "cambio/config/config_error.hpp"

#include <utility>

#include "format.hpp"

namespace cambio::config {

namespace {

std::string describe(const std::vector<ConfigIssue>& issues) {
  if (issues.size() == 1) return issues.front().to_string();
  std::string text = std::to_string(issues.size()) + " configuration problems:";
  for (const auto& issue : issues) text += "\n  " + issue.to_string();
  return text;
}

}  // namespace

std::string ConfigIssue::to_string() const {
  std::string text = file;
  if (line > 0) {
    text += ":" + std::to_string(line);
    if (column > 0) text += ":" + std::to_string(column);
  }
  text += ": ";
  // A key path names keys of the file, which may be long: cut like an echoed value, with room
  // for a few levels of ordinary names.
  if (!key_path.empty()) text += echoed(key_path, 2 * kMaxEchoedChars) + ": ";
  return text + message;
}

ConfigError::ConfigError(std::vector<ConfigIssue> issues)
    : std::runtime_error(describe(issues)), issues_(std::move(issues)) {}

}  // namespace cambio::config
