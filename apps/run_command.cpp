// `cambio run EXPERIMENT.yaml`: the main job (main_job.hpp) with its report.
#include <cmath>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <sstream>

#include "argument_parser.hpp"
#include "builtin_backends.hpp"
#include "command.hpp"
#include "config_errors.hpp"
#include "image_files.hpp"
#include "json_output.hpp"
#include "main_job.hpp"
#include "progress_reporter.hpp"
#include "stop_signal.hpp"

namespace cambio::app {
namespace {

Json summary_json(const config::ExperimentConfig& experiment, const MainJobResult& result) {
  Json json;
  json["experiment"] = experiment.name;
  json["rig"] = experiment.rig.name;
  json["executor"] = result.realtime ? "realtime" : "lockstep";
  json["seed"] = experiment.seed;
  json["simulated_s"] = result.simulated_s;
  json["wall_s"] = result.wall_s;
  json["stopped_by_signal"] = result.stopped_by_signal;
  json["camera_frames"] = result.camera_frames;
  json["stereo_pairs"] = result.stereo_pairs;
  json["mismatched_stereo_pairs"] = result.mismatched_stereo_pairs;
  json["joint_loop"] = {{"watchdog_hold_cycles", result.watchdog_cycles},
                        {"fault_hold_cycles", result.fault_hold_cycles},
                        {"fault_latched_at_end", result.fault_latched_at_end}};
  if (result.perception) {
    const auto& d = result.perception->disparity;
    json["perception"] = {{"frames", result.perception->sequence},
                          {"disparity_valid", d.valid},
                          {"disparity_px", d.disparity_px},
                          {"confidence", d.confidence}};
  }
  if (result.vergence) {
    json["vergence"] = {{"measurements", result.vergence->measurements},
                        {"corrections", result.vergence->corrections},
                        {"final_disparity_px", result.vergence->disparity_px},
                        {"verging_eye_target_rad", result.vergence->verging_target_rad}};
  }
  Json over_budget = Json::array();
  json["loops"] = Json::array();
  for (const auto& loop : result.loops) {
    json["loops"].push_back(runtime::statistics_json(loop));
    if (!runtime::passes_allocation_gate(loop)) over_budget.push_back(loop.name);
  }
  json["allocation_gate"] = {{"passed", over_budget.empty()},
                             {"loops_that_allocated", over_budget}};
  return json;
}

}  // namespace

int run_run_command(std::span<const std::string> args) {
  ArgumentParser parser("run", "EXPERIMENT.yaml [--set KEY=VALUE]... [--out DIR]");
  parser.positional("EXPERIMENT.yaml", "the experiment to run (firmware_config/experiments/)")
      .repeated_option("set", "KEY=VALUE",
                       "override an experiment key (experiment.duration_s=2) or, prefixed with "
                       "rig., a rig key (rig.loops.control.rate_hz=100)")
      .option("out", "DIR", "write each camera's last frame (PNG) and summary.json here");
  if (!parser.parse(args)) return kExitOk;

  std::vector<config::ConfigOverride> overrides;
  config::ExperimentConfig experiment;
  try {
    for (const auto& text : parser.values("set")) overrides.push_back(config::parse_override(text));
    experiment = config::load_experiment(*parser.positional_value("EXPERIMENT.yaml"), overrides);
  } catch (const config::ConfigError& error) {
    report_config_error(error);
    return kExitBadInput;
  }

  hal::BackendFactory factory;
  std::unique_ptr<MainJob> job;
  try {
    register_builtin_backends(factory, experiment);
    job = std::make_unique<MainJob>(experiment, factory);
  } catch (const hal::BackendUnavailable& error) {
    std::cerr << "cambio run: " << error.what() << "\n";
    return kExitBadInput;
  } catch (const config::ConfigError& error) {
    report_config_error(error);
    return kExitBadInput;
  }

  const auto& stop = install_stop_signal_handlers();
  std::cerr << "cambio run: " << experiment.name << " on rig '" << experiment.rig.name << "', "
            << (job->realtime() ? "realtime" : "lockstep") << " executor, " << experiment.duration_s
            << " s, seed " << experiment.seed << "\n";
  if (job->realtime() && experiment.executor == config::ExecutorKind::kLockstep) {
    std::cerr << "cambio run: the rig drives real hardware: running on the realtime executor\n";
  }
  ProgressReporter progress("run", experiment.duration_s);
  const MainJobResult result =
      job->run(stop, [&](double done_s, double wall_s) { progress.update(done_s, wall_s); });
  progress.finish(result.wall_s);
  if (result.stopped_by_signal) std::cerr << "cambio run: stopped by signal\n";

  std::cout << runtime::format_statistics_table(result.loops.data(), result.loops.size());
  std::cout << "camera frames grabbed: " << result.camera_frames << " (" << result.stereo_pairs
            << " stereo pairs, " << result.mismatched_stereo_pairs
            << " refused for mismatched stamps)"
            << ", joint-loop watchdog holds: " << result.watchdog_cycles
            << " cycles, fault/stale holds: " << result.fault_hold_cycles << " cycles\n";
  if (result.fault_latched_at_end) {
    std::cout << "joint loop: a drive fault is latched; the joints hold until a fault reset\n";
  }
  if (result.perception) {
    const auto& d = result.perception->disparity;
    std::cout << "perception: " << result.perception->sequence << " stereo frames; disparity at "
              << "the fovea " << (d.valid ? std::to_string(d.disparity_px) + " px" : "invalid")
              << " (confidence " << d.confidence << ")\n";
  }
  int exit_code = kExitOk;
  if (result.vergence) {
    const double goal = experiment.vergence.goal_disparity_px;
    const bool verged = result.vergence->valid && std::abs(result.vergence->disparity_px) <= goal;
    std::cout << "vergence: " << result.vergence->corrections << " corrections from "
              << result.vergence->measurements << " measurements; final disparity "
              << result.vergence->disparity_px << " px (goal |d| <= " << goal << " px): "
              << (goal <= 0 ? "not scored"
                  : verged  ? "verged"
                            : "NOT verged")
              << "\n";
    if (goal > 0 && !verged && !result.stopped_by_signal) exit_code = kExitFailure;
  }

  if (parser.has("out")) {
    const std::filesystem::path out_dir = parser.value("out");
    std::filesystem::create_directories(out_dir);
    const auto frames = job->last_frames();
    for (std::size_t i = 0; i < frames.size(); ++i) {
      if (frames[i]->sequence == 0) continue;
      write_png((out_dir / (job->cameras()[i].name + ".png")).string(), *frames[i]);
    }
    std::ofstream(out_dir / "summary.json") << json_text(summary_json(experiment, result));
    std::cerr << "cambio run: wrote " << out_dir.string() << "\n";
  }
  return exit_code;
}

}  // namespace cambio::app
