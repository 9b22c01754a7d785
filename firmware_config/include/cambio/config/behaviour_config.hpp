#pragma once

#include <string>
#include <vector>

namespace cambio::config {

/// One of `behaviour.params`: its value as written, checked by the behaviour that reads it.
struct BehaviourParamConfig {
  std::string key;
  std::string text;
  std::string where;  ///< "file:line" of the key.
};

/// An experiment's `behaviour:` (the paper's Decision Making Module): a behaviour by name, built
/// in or from a plugin, run at its own rate and issuing the run's gaze (and arm) commands.
struct BehaviourConfig {
  std::string name;
  double rate_hz = 10.0;
  /// Shared libraries to load before `name` is looked up, resolved against the experiment
  /// file's folder.
  std::vector<std::string> plugins;
  std::vector<BehaviourParamConfig> params;  ///< In file order.
};

}  // namespace cambio::config
