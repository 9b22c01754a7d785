#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "cambio/config/map_reader.hpp"
#include "cambio/config/rig_config.hpp"

namespace cambio::config {

enum class ExecutorKind : std::uint8_t {
  kLockstep,  ///< Simulated time, deterministic for a seed, as fast as the loops allow.
  kRealtime,  ///< Paced to CLOCK_MONOTONIC, a thread per loop.
};

/// One run of the main job (experiments/*.yaml): which rig in which scene, how long, how timed.
struct ExperimentConfig {
  std::string source_file;
  std::string name;
  std::string rig_path;    ///< Resolved against the experiment file's folder.
  std::string scene_path;  ///< Resolved likewise; empty for no scene.
  ExecutorKind executor = ExecutorKind::kLockstep;
  double duration_s = 0.0;
  std::uint64_t seed = 0;
  /// Joints start at the rig's initial_position; change it per run with
  /// `--set rig.joints.<name>.initial_position_deg=...`.
  RigConfig rig;  ///< The loaded rig (rig overrides from the command line applied).
};

/// Loads an experiment and the rig it names. `overrides` apply to the experiment file; keys
/// under `rig.` (e.g. `rig.loops.control.rate_hz=100`) apply to the rig file instead. Throws
/// ConfigError with every problem of both files.
ExperimentConfig load_experiment(const std::string& path,
                                 const std::vector<ConfigOverride>& overrides = {});

}  // namespace cambio::config
