#include <filesystem>

#include "cambio/config/experiment_config.hpp"
#include "cambio/config/rig_loader.hpp"

namespace cambio::config {

ExperimentConfig load_experiment(const std::string& path,
                                 const std::vector<ConfigOverride>& overrides) {
  std::vector<ConfigOverride> experiment_overrides;
  std::vector<ConfigOverride> rig_overrides;
  for (const auto& override_entry : overrides) {
    if (override_entry.key_path.starts_with("rig.")) {
      rig_overrides.push_back({override_entry.key_path.substr(4), override_entry.value});
    } else {
      experiment_overrides.push_back(override_entry);
    }
  }

  ConfigDocument document = ConfigDocument::load_file(path, experiment_overrides);
  MapReader root = document.root();
  MapReader experiment = root.map("experiment");
  root.finish();

  ExperimentConfig config;
  config.source_file = path;
  const std::filesystem::path folder = std::filesystem::path(path).parent_path();
  auto resolve = [&](const std::string& relative) {
    if (relative.empty() || std::filesystem::path(relative).is_absolute()) return relative;
    return (folder / relative).lexically_normal().string();
  };

  config.name = experiment.text("name");
  const std::string rig_file = experiment.text("rig");
  const std::string scene_file = experiment.text_or("scene", "");
  config.rig_path = resolve(rig_file);
  config.scene_path = resolve(scene_file);
  config.executor =
      experiment.choice_or("executor", {"lockstep", "realtime"}, "lockstep") == "realtime"
          ? ExecutorKind::kRealtime
          : ExecutorKind::kLockstep;
  config.duration_s = experiment.number("duration_s", Range::positive());
  config.seed = static_cast<std::uint64_t>(
      experiment.integer_or("seed", 0, Range::closed(0, 9.007199254740992e15)));
  if (!config.rig_path.empty() && !std::filesystem::exists(config.rig_path)) {
    experiment.error("rig", "expected an existing rig file, found \"" + rig_file +
                                "\" (resolved to " + config.rig_path + ")");
  }
  if (!config.scene_path.empty() && !std::filesystem::exists(config.scene_path)) {
    experiment.error("scene", "expected an existing scene file, found \"" + scene_file +
                                  "\" (resolved to " + config.scene_path + ")");
  }
  experiment.finish();
  document.issues()->throw_if_any();

  config.rig = load_rig(config.rig_path, rig_overrides);
  return config;
}

}  // namespace cambio::config
