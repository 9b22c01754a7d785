#include <algorithm>
#include <filesystem>
#include <optional>

#include "cambio/config/experiment_config.hpp"
#include "cambio/config/rig_loader.hpp"
#include "experiment_sections.hpp"
#include "format.hpp"

namespace cambio::config {

namespace {

/// The command-line overrides of an experiment, by the file they apply to.
struct SplitOverrides {
  std::vector<ConfigOverride> experiment;
  std::vector<ConfigOverride> rig;    ///< `rig.` removed.
  std::vector<ConfigOverride> scene;  ///< `scene.` removed.
};

/// Adds every issue of `error` (another file's) to `document`'s.
void add_issues(ConfigDocument& document, const ConfigError& error) {
  for (const auto& issue : error.issues()) document.issues()->add(issue);
}

/// Resolves the paths an experiment names against its file's folder; an absolute path, or none,
/// stays as given.
class PathResolver {
 public:
  explicit PathResolver(const std::string& experiment_path)
      : folder_(std::filesystem::path(experiment_path).parent_path()) {}

  std::string operator()(const std::string& relative) const {
    if (relative.empty() || std::filesystem::path(relative).is_absolute()) return relative;
    return (folder_ / relative).lexically_normal().string();
  }

 private:
  std::filesystem::path folder_;
};

/// What the experiment's keys gave as written: the files it names (for messages, beside the
/// resolved paths in ExperimentConfig) and the task's name.
struct AsWritten {
  std::string rig_file;
  std::string scene_file;
  std::string perception_file;
  std::string task;
};

/// A file the experiment names is checked here, so that a problem with it (missing, a
/// directory, unreadable, a name too long, a symbolic link loop) is reported at the key that
/// names it. Returns whether it can be read.
bool check_named_file(MapReader& experiment, std::string_view key, std::string_view what,
                      const std::string& given, const std::string& resolved) {
  if (resolved.empty()) return false;
  const auto problem = config_file_problem(resolved);
  if (!problem) return true;
  std::string message =
      "expected a readable " + std::string(what) + " file, found " + in_quotes(given);
  if (resolved != given) message += " (resolved to " + in_quotes(resolved) + ")";
  experiment.error(key, message + ": " + *problem);
  return false;
}

/// The run's own settings: its name, the files it names, executor, duration and task.
AsWritten read_run_settings(MapReader& experiment, const PathResolver& resolve,
                            ExperimentConfig& config) {
  AsWritten written;
  config.name = experiment.text("name");
  written.rig_file = experiment.text("rig");
  written.scene_file = experiment.text_or("scene", "");
  config.rig_path = resolve(written.rig_file);
  config.scene_path = resolve(written.scene_file);
  config.executor =
      experiment.choice_or("executor", {"lockstep", "realtime"}, "lockstep") == "realtime"
          ? ExecutorKind::kRealtime
          : ExecutorKind::kLockstep;
  config.duration_s = experiment.number(
      "duration_s", Range{0.0, kMaxExperimentDuration_s, true, false}.because(
                        "a day; a run's cycles, progress and records grow with its duration"));
  written.perception_file = experiment.text_or("perception", "");
  config.perception_path = resolve(written.perception_file);
  written.task = experiment.choice_or("task", {"hold", "gaze"}, "hold");
  config.task = written.task == "gaze" ? ControlTask::kGaze : ControlTask::kHold;
  return written;
}

void read_fault_recovery(MapReader& experiment, ExperimentConfig& config) {
  if (auto recovery = experiment.optional_map("fault_recovery")) {
    FaultRecoveryConfig& r = config.fault_recovery;
    r.after_s = recovery->number_or("after_s", r.after_s, Range::closed(0.0, 3600.0));
    r.max_recoveries = static_cast<int>(
        recovery->integer_or("max_recoveries", r.max_recoveries, Range::closed(0, 1000)));
    r.home_after_reboot = recovery->boolean_or("home_after_reboot", r.home_after_reboot);
    recovery->finish();
  }
}

void read_ros2(MapReader& experiment, ExperimentConfig& config) {
  if (auto section = experiment.optional_map("ros2")) {
    Ros2Config& ros2 = config.ros2.emplace();
    // RTPS puts a domain's ports at 7400 + 250 * id: above 232 they leave the 16-bit range.
    ros2.domain_id = static_cast<int>(section->integer_or(
        "domain_id", ros2.domain_id,
        Range::closed(0, 232).because("RTPS's ports for a higher domain exceed 65535")));
    ros2.joint_states_hz =
        section->number_or("joint_states_hz", ros2.joint_states_hz, Range::closed(0.0, 1000.0));
    ros2.clock = section->boolean_or("clock", ros2.clock);
    ros2.tf = section->boolean_or("tf", ros2.tf);
    ros2.images_hz = section->number_or("images_hz", ros2.images_hz, Range::closed(0.0, 1000.0));
    ros2.diagnostics_hz =
        section->number_or("diagnostics_hz", ros2.diagnostics_hz, Range::closed(0.0, 1000.0));
    ros2.gaze_hz = section->number_or("gaze_hz", ros2.gaze_hz, Range::closed(0.0, 1000.0));
    ros2.commands = section->boolean_or("commands", ros2.commands);
    ros2.split =
        section->choice_or("split", {"none", "perception_remote"}, "none") == "perception_remote"
            ? Ros2Config::Split::kPerceptionRemote
            : Ros2Config::Split::kNone;
    ros2.link_timeout_s =
        section->number_or("link_timeout_s", ros2.link_timeout_s, Range::closed(0.05, 10.0));
    ros2.host_wait_s =
        section->number_or("host_wait_s", ros2.host_wait_s, Range::closed(0.0, 600.0));
    section->finish();
  }
}

/// ROS 2 commands drive the gaze loop, whose command channel takes one writer: a behaviour
/// would be a second (the script's `commands` are refused where they are read).
void check_ros2_commands(MapReader& experiment, const ExperimentConfig& config) {
  if (!config.ros2 || !config.ros2->commands) return;
  if (config.task != ControlTask::kGaze) {
    experiment.error("ros2", "commands: true needs task gaze (the gaze loop takes the commands)");
  } else if (config.behaviour) {
    experiment.error("ros2",
                     "commands: true takes the gaze loop's commands from ROS 2; this experiment's "
                     "behaviour sends its own: keep one");
  }
}

/// Perception on another host: the run must wait for it in wall time, and only the SSM's
/// summaries cross the network (a behaviour reads its feature maps too).
void check_ros2_split(MapReader& experiment, const ExperimentConfig& config) {
  if (!config.ros2 || config.ros2->split != Ros2Config::Split::kPerceptionRemote) return;
  if (config.executor != ExecutorKind::kRealtime) {
    experiment.error("ros2",
                     "split: perception_remote needs executor: realtime (a lockstep run "
                     "keeps simulated time and cannot wait for another host)");
  }
  if (config.task != ControlTask::kGaze) {
    experiment.error("ros2",
                     "split: perception_remote needs task gaze (the gaze loop is what "
                     "uses the perception host's results)");
  } else if (config.behaviour) {
    experiment.error("ros2",
                     "split: perception_remote cannot host a behaviour here: it reads "
                     "the SSM's feature maps, which stay on the perception host");
  }
}

/// The vergence task (a top-level `vergence:`) was retired for the gaze task's vergence; the key
/// is read here so that an old file is told where it went rather than that it is unknown.
void report_retired_vergence(MapReader& experiment) {
  if (experiment.optional_map("vergence")) {
    experiment.error("vergence",
                     "task vergence was retired: use task gaze, with these settings under "
                     "gaze.vergence (the verging eye is the one gaze.dominant_eye is not)");
  }
}

/// Loads the scene the experiment names, its problems joining the experiment's; `scene.`
/// overrides with no scene named are reported as having nowhere to go.
void load_named_scene(ConfigDocument& document, MapReader& experiment, const AsWritten& written,
                      const SplitOverrides& overrides, ExperimentConfig& config) {
  const bool scene_readable =
      check_named_file(experiment, "scene", "scene", written.scene_file, config.scene_path);
  if (scene_readable) {
    try {
      config.scene = load_scene(config.scene_path, overrides.scene);
    } catch (const ConfigError& error) {
      add_issues(document, error);
    }
  } else if (written.scene_file.empty()) {
    for (const auto& override_entry : overrides.scene) {
      document.issues()->add({"--set", 0, 0, "scene." + override_entry.key_path,
                              "the experiment names no scene (experiment.scene) to set it in"});
    }
  }
}

/// The gaze task's sections; a hold run reads none of them, and says so for each one given.
void read_task_sections(MapReader& experiment, const PathResolver& resolve,
                        const SceneForSections& scene,
                        std::vector<PendingPixelTarget>& pixel_targets, ExperimentConfig& config) {
  if (config.task == ControlTask::kGaze) {
    if (auto gaze = experiment.optional_map("gaze")) config.gaze = read_gaze_task(std::move(*gaze));
    if (auto arm = experiment.optional_map("arm")) config.arm = read_arm_task(std::move(*arm));
    if (auto behaviour = experiment.optional_map("behaviour")) {
      config.behaviour = read_behaviour(std::move(*behaviour), resolve);
      // The gaze command channel has one writer: the behaviour or the script.
      if (experiment.has("commands")) {
        experiment.error("commands",
                         "a run with a behaviour takes its gaze commands from it: give either "
                         "behaviour or commands, not both");
      }
    } else if (config.ros2 && config.ros2->commands) {
      // Likewise ROS 2 (/cambio/look_at) or the script.
      if (experiment.has("commands")) {
        experiment.error("commands",
                         "a run with ros2.commands takes its gaze commands from ROS 2: give "
                         "either ros2.commands or commands, not both");
      }
    } else {
      config.commands = read_gaze_commands(experiment, config.duration_s, scene, pixel_targets);
    }
  } else {
    for (const std::string_view key : {"gaze", "arm", "commands", "behaviour"}) {
      if (experiment.has(key)) {
        experiment.error(key, "only task gaze reads " + std::string(key) + " (task is hold)");
      }
    }
  }
}

/// Loads the rig when its file can be read, its problems joining the experiment's. Returns
/// whether it loaded.
bool load_named_rig(ConfigDocument& document, bool rig_readable, const SplitOverrides& overrides,
                    ExperimentConfig& config) {
  if (!rig_readable) return false;
  try {
    config.rig = load_rig(config.rig_path, overrides.rig);
    return true;
  } catch (const ConfigError& error) {
    add_issues(document, error);
  }
  return false;
}

void apply_initial_pose(MapReader& pose, RigConfig& rig) {
  // Every joint's key is read, so that a key naming no joint is offered all of them.
  for (auto& joint : rig.joints) {
    joint.initial_position_rad =
        pose.angle_rad_or(joint.name, joint.initial_position_rad,
                          Range::closed(joint.min_position_rad, joint.max_position_rad)
                              .because("the joint's limits in the rig"));
  }
  pose.finish();  // Keys naming no joint are reported here, with a "did you mean".
}

/// What the task asks of the loaded rig: a stereo pair for gaze, arms for scripted arm
/// commands, and pixel targets inside the dominant eye's image.
void check_rig_serves_task(MapReader& experiment, const AsWritten& written,
                           std::vector<PendingPixelTarget>& pixel_targets,
                           const ExperimentConfig& config) {
  if (config.task != ControlTask::kHold && !config.rig.stereo) {
    experiment.error("task", "expected a rig with a stereo pair for the " + written.task +
                                 " task, found none in " + config.rig_path);
  }
  const bool scripts_arms =
      std::any_of(config.commands.begin(), config.commands.end(),
                  [](const GazeCommandConfig& c) { return c.arm.has_value(); });
  if (scripts_arms && config.rig.touch_sensors.empty()) {
    experiment.error("commands",
                     "expected a rig with arms for reach, grasp or release (an arm "
                     "group with a touch sensor on its gripper), found no touch "
                     "sensor in " +
                         config.rig_path);
  }
  if (config.rig.stereo && !pixel_targets.empty()) {
    const StereoConfig& stereo = *config.rig.stereo;
    const CameraConfig* dominant = config.rig.find_camera(
        config.gaze.dominant_eye == hal::Eye::kLeft ? stereo.left_camera : stereo.right_camera);
    if (dominant != nullptr) check_pixel_targets(pixel_targets, *dominant);
  }
}

/// Reads the experiment in `document` (from file `path`, against whose folder relative paths
/// resolve), loads the rig and scene it names with their overrides, and throws every problem of
/// the three.
ExperimentConfig read_experiment(ConfigDocument& document, const std::string& path,
                                 const SplitOverrides& overrides) {
  MapReader root = document.root();
  MapReader experiment = root.map("experiment");
  root.finish();

  ExperimentConfig config;
  config.source_file = path;
  const PathResolver resolve(path);
  const AsWritten written = read_run_settings(experiment, resolve, config);
  read_fault_recovery(experiment, config);
  read_ros2(experiment, config);
  report_retired_vergence(experiment);
  // The scene is loaded before the sections that name its objects.
  load_named_scene(document, experiment, written, overrides, config);
  const SceneForSections scene{config.scene ? &*config.scene : nullptr,
                               !written.scene_file.empty()};
  // Pixel targets are checked against the dominant eye's image once the rig is loaded.
  std::vector<PendingPixelTarget> pixel_targets;
  read_task_sections(experiment, resolve, scene, pixel_targets, config);
  check_ros2_commands(experiment, config);
  check_ros2_split(experiment, config);
  if (auto evaluation = experiment.optional_map("evaluation")) {
    config.evaluation = read_evaluation(std::move(*evaluation), config.duration_s, scene);
  }
  config.goals = read_goals(experiment);
  config.seed = static_cast<std::uint64_t>(
      experiment.integer_or("seed", 0, Range::closed(0, 9.007199254740992e15)));
  const bool rig_readable =
      check_named_file(experiment, "rig", "rig", written.rig_file, config.rig_path);
  check_named_file(experiment, "perception", "perception config", written.perception_file,
                   config.perception_path);
  // The initial pose names rig joints, so it is checked once the rig is loaded. Problems of
  // both files are reported together.
  std::optional<MapReader> pose = experiment.optional_map("initial_pose");
  if (!load_named_rig(document, rig_readable, overrides, config)) {
    experiment.finish();
    document.issues()->throw_if_any();
  }
  if (pose) apply_initial_pose(*pose, config.rig);
  check_rig_serves_task(experiment, written, pixel_targets, config);
  experiment.finish();
  document.issues()->throw_if_any();
  return config;
}

/// Splits `overrides` into the experiment's, the rig's (`rig.` prefix removed) and the scene's
/// (`scene.` removed).
SplitOverrides split_overrides(const std::vector<ConfigOverride>& overrides) {
  SplitOverrides split;
  for (const auto& override_entry : overrides) {
    if (override_entry.key_path.starts_with("rig.")) {
      split.rig.push_back({override_entry.key_path.substr(4), override_entry.value});
    } else if (override_entry.key_path.starts_with("scene.")) {
      split.scene.push_back({override_entry.key_path.substr(6), override_entry.value});
    } else {
      split.experiment.push_back(override_entry);
    }
  }
  return split;
}

}  // namespace

ExperimentConfig load_experiment(const std::string& path,
                                 const std::vector<ConfigOverride>& overrides) {
  const SplitOverrides split = split_overrides(overrides);
  ConfigDocument document = ConfigDocument::load_file(path, split.experiment);
  return read_experiment(document, path, split);
}

ExperimentConfig load_experiment_from_string(const std::string& yaml, const std::string& name,
                                             const std::vector<ConfigOverride>& overrides) {
  const SplitOverrides split = split_overrides(overrides);
  ConfigDocument document = ConfigDocument::from_string(yaml, name, split.experiment);
  return read_experiment(document, name, split);
}

}  // namespace cambio::config
