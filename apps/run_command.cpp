// `cambio run EXPERIMENT.yaml`: the main job. Builds the rig's backends through the factory,
// wires the loops (camera, control, joint, and the backends' own) through latest-value
// channels, and runs them under the experiment's executor.
#include <chrono>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <map>
#include <memory>

#include "argument_parser.hpp"
#include "builtin_backends.hpp"
#include "cambio/config/experiment_config.hpp"
#include "cambio/control/joint_loop.hpp"
#include "cambio/hal/manual_clock.hpp"
#include "cambio/runtime/lockstep_executor.hpp"
#include "cambio/runtime/realtime_executor.hpp"
#include "camera_loop.hpp"
#include "command.hpp"
#include "config_errors.hpp"
#include "image_files.hpp"
#include "progress_reporter.hpp"
#include "stop_signal.hpp"

namespace cambio::app {
namespace {

// The joint loop holds position if the control loop's targets are older than this.
constexpr double kCommandTimeoutS = 0.1;

/// Until the gaze controllers land, the control loop holds the rig's initial pose: the joint
/// loop's watchdog, limits and rate limits still act on every cycle.
class PoseHoldLoop final : public hal::Loop {
 public:
  PoseHoldLoop(control::JointTargetFrame pose, hal::SeqlockChannel<control::JointTargetFrame>& out)
      : pose_(pose), out_(out) {}
  const std::string& name() const override { return name_; }
  hal::Status update(const hal::LoopTick& tick) noexcept override {
    pose_.stamp_ns = tick.now_ns;
    out_.write(pose_);
    return hal::Status::kOk;
  }

 private:
  std::string name_ = "control";
  control::JointTargetFrame pose_;
  hal::SeqlockChannel<control::JointTargetFrame>& out_;
};

const config::LoopConfig& loop_schedule(const config::RigConfig& rig, const std::string& name) {
  const config::LoopConfig* loop = rig.find_loop(name);
  if (loop == nullptr) throw std::runtime_error("rig defines no '" + name + "' loop");
  return *loop;
}

}  // namespace

int run_run_command(std::span<const std::string> args) {
  ArgumentParser parser("run", "EXPERIMENT.yaml [--set KEY=VALUE]... [--out DIR]");
  parser.positional("EXPERIMENT.yaml", "the experiment to run (firmware_config/experiments/)")
      .repeated_option("set", "KEY=VALUE",
                       "override an experiment key (experiment.duration_s=2) or, prefixed with "
                       "rig., a rig key (rig.loops.control.rate_hz=100)")
      .option("out", "DIR", "write the last stereo frames and the loop statistics (JSON) here");
  if (!parser.parse(args)) return kExitOk;

  std::vector<config::ConfigOverride> overrides;
  for (const auto& text : parser.values("set")) overrides.push_back(config::parse_override(text));
  config::ExperimentConfig experiment;
  try {
    experiment = config::load_experiment(*parser.positional_value("EXPERIMENT.yaml"), overrides);
  } catch (const config::ConfigError& error) {
    report_config_error(error);
    return kExitBadInput;
  }
  const config::RigConfig& rig = experiment.rig;
  const bool realtime = experiment.executor == config::ExecutorKind::kRealtime;

  // One backend instance per backend name, shared by the groups and cameras naming it.
  hal::BackendFactory factory;
  register_builtin_backends(factory);
  const hal::BackendOptions options{experiment.scene_path, experiment.seed, realtime};
  std::map<std::string, std::unique_ptr<hal::Backend>> backends;
  auto backend_for = [&](const std::string& name, const std::string& requested_by) -> hal::Backend& {
    auto& slot = backends[name];
    if (!slot) slot = factory.make(name, rig, options, requested_by);
    return *slot;
  };

  std::vector<std::unique_ptr<hal::JointGroup>> groups;
  std::vector<std::unique_ptr<hal::Camera>> cameras;
  try {
    for (const auto& group : rig.groups) {
      groups.push_back(backend_for(group.backend, "joint group '" + group.name + "'")
                           .make_joint_group(group.name));
    }
    for (const auto& camera : rig.cameras) {
      cameras.push_back(
          backend_for(camera.backend, "camera '" + camera.name + "'").make_camera(camera.name));
    }
  } catch (const hal::BackendUnavailable& error) {
    std::cerr << "cambio run: " << error.what() << "\n";
    return kExitBadInput;
  }

  // Channels between the loops.
  hal::SeqlockChannel<control::JointTargetFrame> targets;
  hal::SeqlockChannel<control::JointStateFrame> states;
  control::JointTargetFrame initial_pose;
  std::vector<hal::JointGroup*> group_pointers;
  for (std::size_t g = 0; g < groups.size(); ++g) {
    group_pointers.push_back(groups[g].get());
    for (const auto& joint_name : rig.groups[g].joints) {
      const config::JointConfig* joint = rig.find_joint(joint_name);
      initial_pose.commands[static_cast<std::size_t>(initial_pose.count++)] = {
          hal::CommandMode::kPosition, joint->initial_position_rad};
    }
  }
  std::vector<hal::Camera*> camera_pointers;
  for (const auto& camera : cameras) camera_pointers.push_back(camera.get());

  control::JointLoop joint_loop(group_pointers, targets, states, kCommandTimeoutS);
  PoseHoldLoop control_loop(initial_pose, targets);
  CameraLoop camera_loop(camera_pointers);

  std::vector<runtime::ScheduledLoop> scheduled = {
      {&joint_loop, loop_schedule(rig, "joint")},
      {&control_loop, loop_schedule(rig, "control")},
      {&camera_loop, loop_schedule(rig, "camera")},
  };
  for (auto& [name, backend] : backends) {
    for (const hal::BackendLoop& backend_loop : backend->loops()) {
      config::LoopConfig schedule;
      schedule.name = backend_loop.loop->name();
      schedule.rate_hz = backend_loop.rate_hz;
      schedule.priority = backend_loop.priority;
      scheduled.push_back({backend_loop.loop, schedule});
    }
  }

  hal::Clock& clock = backends.begin()->second->clock();
  const auto& stop = install_stop_signal_handlers();
  std::cerr << "cambio run: " << experiment.name << " on rig '" << rig.name << "', "
            << (realtime ? "realtime" : "lockstep") << " executor, " << experiment.duration_s
            << " s, seed " << experiment.seed << "\n";

  const auto wall_start = std::chrono::steady_clock::now();
  auto wall_elapsed_s = [&] {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - wall_start).count();
  };
  ProgressReporter progress("run", experiment.duration_s);
  std::vector<runtime::LoopStatistics> statistics;
  if (realtime) {
    runtime::RealtimeExecutor executor(clock, scheduled, {rig.runtime.lock_memory});
    executor.run(stop, static_cast<std::int64_t>(experiment.duration_s * 1e9));
    statistics = executor.statistics();
  } else {
    auto* sim_clock = dynamic_cast<hal::ManualClock*>(&clock);
    if (sim_clock == nullptr) {
      std::cerr << "cambio run: the lockstep executor needs simulated time, but backend '"
                << backends.begin()->first
                << "' runs on the wall clock; set experiment.executor: realtime\n";
      return kExitBadInput;
    }
    runtime::LockstepExecutor executor(*sim_clock, scheduled);
    executor.configure();
    const std::int64_t start_ns = sim_clock->now_ns();
    const auto total_ns = static_cast<std::int64_t>(experiment.duration_s * 1e9);
    constexpr std::int64_t kChunkNs = 100'000'000;  // Report progress every 0.1 s of sim time.
    for (std::int64_t done = 0; done < total_ns && !stop.load();) {
      done = std::min(total_ns, done + kChunkNs);
      executor.run_until_ns(start_ns + done);
      progress.update(static_cast<double>(done) * 1e-9, wall_elapsed_s());
    }
    executor.deactivate();
    statistics = executor.statistics();
  }
  progress.finish(wall_elapsed_s());
  if (stop.load()) std::cerr << "cambio run: stopped by signal\n";

  std::cout << runtime::format_statistics_table(statistics.data(), statistics.size());
  std::cout << "camera frames grabbed: " << camera_loop.frames_grabbed()
            << ", joint-loop watchdog holds: " << joint_loop.stale_cycles() << " cycles\n";

  if (parser.has("out")) {
    const std::filesystem::path out_dir = parser.value("out");
    std::filesystem::create_directories(out_dir);
    for (std::size_t i = 0; i < cameras.size(); ++i) {
      auto& channel = camera_loop.frames(i);
      channel.acquire();
      if (channel.front().sequence == 0) continue;
      write_png((out_dir / (rig.cameras[i].name + ".png")).string(), channel.front());
    }
    std::ofstream json(out_dir / "loops.json");
    json << "{\"experiment\": \"" << experiment.name << "\", \"loops\": [";
    for (std::size_t i = 0; i < statistics.size(); ++i) {
      json << (i == 0 ? "" : ", ") << runtime::statistics_json(statistics[i]);
    }
    json << "]}\n";
    std::cerr << "cambio run: wrote " << out_dir.string() << "\n";
  }
  return kExitOk;
}

}  // namespace cambio::app
