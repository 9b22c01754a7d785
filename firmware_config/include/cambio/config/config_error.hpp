#pragma once

#include <stdexcept>
#include <string>
#include <vector>

namespace cambio::config {

/// One problem in a configuration, located precisely enough to fix it without searching.
struct ConfigIssue {
  std::string file;      ///< Path of the YAML file, or "--set" for a command-line override.
  int line = 0;          ///< 1-based; 0 when unknown (e.g. a key that is missing from a map
                         ///< is reported at the map's own line).
  int column = 0;        ///< 1-based.
  std::string key_path;  ///< e.g. "joints.neck_pan.max_velocity_rad_s".
  std::string message;   ///< What was expected and what was found.

  /// "file:line:column: key.path: message" (the form compilers use, so editors can jump).
  std::string to_string() const;
};

/// Thrown by loaders after reading everything: carries every problem found, not just the first.
class ConfigError : public std::runtime_error {
 public:
  explicit ConfigError(std::vector<ConfigIssue> issues);
  const std::vector<ConfigIssue>& issues() const { return issues_; }

 private:
  std::vector<ConfigIssue> issues_;
};

}  // namespace cambio::config
