#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "cambio/config/arm_task_config.hpp"
#include "cambio/config/behaviour_config.hpp"
#include "cambio/config/experiment_evaluation.hpp"
#include "cambio/config/gaze_task_config.hpp"
#include "cambio/config/map_reader.hpp"
#include "cambio/config/rig_config.hpp"
#include "cambio/config/scene_config.hpp"

namespace cambio::config {

enum class ExecutorKind : std::uint8_t {
  kLockstep,  ///< Simulated time, deterministic for a seed, as fast as the loops allow.
  kRealtime,  ///< Paced to CLOCK_MONOTONIC, a thread per loop.
};

/// What the control loop does during the run.
enum class ControlTask : std::uint8_t {
  kHold,  ///< Hold the initial pose (the joint loop's limits and watchdog still act).
  kGaze,  ///< The gaze loop: fixation, saccades, pursuit and vergence, run by `commands`.
};

/// What the run does when a drive fault or a lost drive is latched (`fault_recovery:`): by
/// default it holds to the end and exits 3; with recoveries, after holding `after_s` it asks a
/// fault reset and re-enables the drives where they stand, at most `max_recoveries` times. With
/// `home_after_reboot`, a joint that homes and whose drive rebooted (its reference lost) homes
/// again before it is enabled; without, it stays disabled until homed on request.
struct FaultRecoveryConfig {
  double after_s = 0.5;
  int max_recoveries = 0;
  bool home_after_reboot = false;
};

/// The run as a ROS 2 node (`ros2:`): what it publishes over DDS (Cyclone, configured by its own
/// CYCLONEDDS_URI), and on which domain.
struct Ros2Config {
  int domain_id = 0;              ///< ROS_DOMAIN_ID: 0-232.
  double joint_states_hz = 50.0;  ///< /joint_states per second of wall time; 0: none.
  bool clock = true;              ///< /clock on simulated-time (lockstep) runs.
  bool tf = true;                 ///< /tf with each joint state, /tf_static once.
  double images_hz = 15.0;        ///< The stereo pair's images per second of wall time; 0: none.
  double diagnostics_hz = 1.0;    ///< /diagnostics per second of wall time; 0: none.
  double gaze_hz = 10.0;          ///< /cambio/gaze/fixation and status per second; 0: none.
  /// Take gaze commands from ROS 2 (/cambio/look_at): the gaze task with no `commands` and no
  /// `behaviour` (the gaze loop takes one writer).
  bool commands = false;
  /// Where the stack is split across machines: kNone runs it all here; kPerceptionRemote sends
  /// the stereo pairs to a perception host (`cambio node perception`) and takes its SSM results
  /// back (realtime executor only: a lockstep run cannot wait for another host).
  enum class Split { kNone, kPerceptionRemote };
  Split split = Split::kNone;
  /// kPerceptionRemote: no result for this long while pairs go out is a lost link (reported;
  /// the gaze holds until results come again).
  double link_timeout_s = 0.3;
  /// kPerceptionRemote: how long the run waits, before it starts, for the perception host.
  double host_wait_s = 10.0;
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
  /// The perception (SSM) settings file; empty: the shipped default.
  std::string perception_path;
  ControlTask task = ControlTask::kHold;
  /// kGaze only: the gaze loop's settings and its commands (in time order; at least one unless
  /// a behaviour gives them).
  GazeTaskConfig gaze;
  /// kGaze only: the arms' reach settings (`arm:`), used when the rig has arms.
  ArmTaskConfig arm;
  std::vector<GazeCommandConfig> commands;
  /// kGaze only: the behaviour that commands the gaze instead of `commands` (the two exclude
  /// each other: the gaze command channel has one writer).
  std::optional<BehaviourConfig> behaviour;
  EvaluationConfig evaluation;
  std::vector<GoalConfig> goals;  ///< In file order; empty: nothing scored by name.
  FaultRecoveryConfig fault_recovery;
  std::optional<Ros2Config> ros2;  ///< Absent: the run talks to no ROS 2 node.
  /// The loaded rig, overrides from the command line applied, and the experiment's
  /// `initial_pose` (joint name -> `<joint>_deg` or `<joint>_rad`) written into each joint's
  /// initial_position_rad.
  RigConfig rig;
  /// The loaded scene (scene_path), `scene.` overrides applied; nullopt for no scene. Everyone
  /// uses this one (the sim's world, object targets, evaluation), so they cannot disagree.
  std::optional<SceneConfig> scene;
};

/// The longest run an experiment may ask for: a day. A run's cycles (duration x each loop's
/// rate), its progress and whatever it records per cycle grow with it.
inline constexpr double kMaxExperimentDuration_s = 86'400.0;

/// Loads an experiment and the rig and scene it names. `overrides` apply to the experiment file;
/// keys under `rig.` (e.g. `rig.loops.control.rate_hz=100`) apply to the rig file instead, and
/// keys under `scene.` to the scene file (objects by index: `scene.objects.0.xyz_m=[1, 0, 1.4]`).
/// Throws ConfigError with every problem of the three files; a rig, scene or perception file that
/// cannot be read (see config_file_problem) is reported at the experiment's key that names it.
ExperimentConfig load_experiment(const std::string& path,
                                 const std::vector<ConfigOverride>& overrides = {});
/// The same from YAML text: `name` stands for the file in messages, and the rig, scene and
/// perception paths resolve against its folder.
ExperimentConfig load_experiment_from_string(const std::string& yaml, const std::string& name,
                                             const std::vector<ConfigOverride>& overrides = {});

}  // namespace cambio::config
