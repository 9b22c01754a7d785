// `cambio run EXPERIMENT.yaml`: the main job (main_job.hpp) with its report.
#include <csignal>
#include <iostream>
#include <memory>
#include <numbers>
#include <optional>

#include "argument_parser.hpp"
#include "builtin_backends.hpp"
#include "cambio/can/can_traffic_log.hpp"
#include "command.hpp"
#include "config_errors.hpp"
#include "controller_params.hpp"
#include "image_files.hpp"
#include "json_output.hpp"
#include "main_job.hpp"
#include "output_directory.hpp"
#include "peak_rss.hpp"
#include "progress_reporter.hpp"
#include "renderer_report.hpp"
#include "run_metrics.hpp"
#include "run_plots.hpp"
#include "stop_signal.hpp"

namespace cambio::app {
namespace {

struct RunOutcome {
  std::string name;  ///< completed, goal_failed, behaviour_failed, device_fault, interrupted.
  int exit_status = 0;
  std::string signal_name;  ///< Set when a signal stopped the run.
};

/// What the trace says about the run: its metrics and the experiment's goals on them.
struct RunEvaluation {
  RunMetrics metrics;
  std::vector<GoalResult> goals;
};

Json summary_json(const config::ExperimentConfig& experiment, const MainJobResult& result,
                  const RunOutcome& outcome, const Trace* trace,
                  const std::optional<RunEvaluation>& evaluation) {
  Json json;
  json["experiment"] = experiment.name;
  json["outcome"] = outcome.name;
  json["exit_status"] = outcome.exit_status;
  json["stopped_by"] = outcome.signal_name.empty() ? Json(nullptr) : Json(outcome.signal_name);
  json["duration_s"] = experiment.duration_s;
  json["rig"] = experiment.rig.name;
  json["executor"] = result.realtime ? "realtime" : "lockstep";
  json["seed"] = experiment.seed;
  json["simulated_s"] = result.simulated_s;
  json["wall_s"] = result.wall_s;
  json["stopped_by_signal"] = result.stopped_by_signal;
  json["camera_frames"] = result.camera_frames;
  json["stereo_pairs"] = result.stereo_pairs;
  json["mismatched_stereo_pairs"] = result.mismatched_stereo_pairs;
  json["joint_loop"] = {{"fault_recoveries", result.fault_recoveries},
                        {"startup_hold_cycles", result.startup_hold_cycles},
                        {"watchdog_hold_cycles", result.watchdog_cycles},
                        {"fault_hold_cycles", result.fault_hold_cycles},
                        {"fault_latched_at_end", result.fault_latched_at_end}};
  if (result.perception) {
    const auto& d = result.perception->disparity;
    json["perception"] = {{"frames", result.perception->sequence},
                          {"disparity_valid", d.valid},
                          {"disparity_px", d.disparity_px},
                          {"confidence", d.confidence}};
  }
  if (result.gaze) {
    const control::GazeStatus& gaze = *result.gaze;
    json["gaze"] = {{"commands_applied", gaze.commands_applied},
                    {"commands_rejected", result.gaze_rejected_commands},
                    {"last_refusal", std::string(control::to_string(gaze.last_refusal))},
                    {"disparity_measurements", result.gaze_measurements},
                    {"vergence_corrections", result.gaze_corrections},
                    {"final_action", gaze_action_name(gaze.action)},
                    {"final_vergence_rad", gaze.vergence_rad}};
  }
  if (result.behaviour) {
    const BehaviourReport& behaviour = *result.behaviour;
    json["behaviour"] = {{"name", behaviour.name},
                         {"plugins", behaviour.plugins},
                         {"steps", behaviour.steps},
                         {"status", behaviour.status},
                         {"failed", behaviour.failed},
                         {"error", behaviour.failed ? Json(behaviour.error) : Json(nullptr)}};
  }
  if (result.arms) {
    const control::ArmStatus& arms = *result.arms;
    Json sides = Json::object();
    for (std::size_t side = 0; side < 2; ++side) {
      if (!result.arm_present[side]) continue;
      const control::ArmStatus::Arm& arm = arms.arms[side];
      const auto seconds = [&](std::int64_t ns) {
        return ns == 0 ? Json(nullptr)
                       : Json(static_cast<double>(ns - result.script_start_ns) * 1e-9);
      };
      sides[side == 0 ? "left" : "right"] = {{"phase", reach_phase_name(arm.phase)},
                                             {"gripper_closed", arm.gripper_closed},
                                             {"command_s", seconds(arm.command_ns)},
                                             {"touch_s", seconds(arm.touch_ns)},
                                             {"target_m", arm.target_W_m},
                                             {"gripper_m", arm.gripper_W_m},
                                             {"distance_to_target_m", arm.distance_to_target_m}};
    }
    json["arms"] = {
        {"commands_applied", arms.commands_applied},
        {"refusal", arms.refusal().empty() ? Json(nullptr) : Json(std::string(arms.refusal()))},
        {"arms", sides}};
  }
  if (evaluation) {
    json["metrics"] = metrics_json(evaluation->metrics);
    json["goals"] = goals_json(evaluation->goals);
    json["passed"] = all_passed(evaluation->goals);
  }
  if (trace != nullptr) {
    if (!trace->visit_objects.empty()) {
      json["visits"] = visits_json(*trace, experiment.evaluation.visit_dwell_s);
    }
    json["final_joints"] = final_joints_json(*trace);
    json["trace"] = {{"rows", trace->rows.size()},
                     {"truncated", trace->truncated},
                     {"problems", trace->problems}};
  }
  Json over_budget = Json::array();
  json["loops"] = Json::array();
  for (const auto& loop : result.loops) {
    json["loops"].push_back(runtime::statistics_json(loop));
    if (!runtime::passes_allocation_gate(loop)) over_budget.push_back(loop.name);
  }
  for (const auto& report : result.can_groups) {
    const auto& c = report.counters;
    json["can_groups"][report.group] = {{"syncs_sent", c.syncs_sent},
                                        {"tpdos_received", c.tpdos_received},
                                        {"missed_sync_answers", c.missed_sync_answers},
                                        {"late_tpdos", c.late_tpdos},
                                        {"malformed_frames", c.malformed_frames},
                                        {"unexpected_frames", c.unexpected_frames},
                                        {"tx_queue_full", c.tx_queue_full},
                                        {"emergencies", c.emergencies},
                                        {"error_frames", c.error_frames},
                                        {"boot_ups", c.boot_ups},
                                        {"receive_cap_reached", c.receive_cap_reached}};
  }
  if (result.renderer) {
    add_renderer_fields(json["renderer"], *result.renderer);
  } else {
    json["renderer"] = nullptr;
  }
  json["wall_time_shares"] = runtime::wall_time_shares_json(
      runtime::wall_time_shares(result.loops.data(), result.loops.size(), result.wall_s),
      result.wall_s, !result.realtime);
  json["peak_rss_kib"] = peak_rss_kib();
  json["allocation_gate"] = {{"passed", over_budget.empty()},
                             {"loops_that_allocated", over_budget}};
  return json;
}

/// When the scripted command of `action` last went out (s since the run's start), if it did.
std::optional<double> last_command_time(const config::ExperimentConfig& experiment,
                                        const MainJobResult& result, config::GazeAction action) {
  std::optional<double> time_s;
  for (std::size_t i = 0; i < experiment.commands.size() && i < result.command_sent_s.size(); ++i) {
    if (!experiment.commands[i].arm && experiment.commands[i].action == action &&
        result.command_sent_s[i] >= 0.0) {
      time_s = result.command_sent_s[i];
    }
  }
  return time_s;
}

RunEvaluation evaluate_run(const config::ExperimentConfig& experiment, const MainJobResult& result,
                           const Trace& trace) {
  MetricInputs inputs;
  for (std::size_t i = 0; i < experiment.commands.size() && i < result.command_sent_s.size(); ++i) {
    if (result.command_sent_s[i] < 0.0) continue;  // The run ended before it was due.
    if (experiment.commands[i].arm) continue;      // The arms': no gaze metric's business.
    inputs.commands.push_back(
        {result.command_sent_s[i], gaze_action(experiment.commands[i].action)});
  }
  inputs.settle_disparity_px = experiment.evaluation.settle.disparity_px;
  inputs.settle_gaze_error_deg =
      experiment.evaluation.settle.gaze_error_rad * 180.0 / std::numbers::pi;
  inputs.pursuit_catch_up_s = experiment.evaluation.pursuit_catch_up_s;
  inputs.visit_dwell_s = experiment.evaluation.visit_dwell_s;
  RunEvaluation evaluation{compute_metrics(trace, inputs), {}};
  evaluation.goals = evaluate_goals(evaluation.metrics, experiment.goals);
  return evaluation;
}

void print_evaluation(const RunEvaluation& evaluation) {
  std::cout << "metrics:";
  for (const auto& [name, value] : evaluation.metrics.values)
    std::cout << " " << name << "=" << value;
  std::cout << "\n";
  for (const auto& goal : evaluation.goals) {
    std::cout << "goal " << goal.goal.metric
              << (goal.goal.bound == config::GoalBound::kMax ? " <= " : " >= ") << goal.goal.value
              << ": " << (goal.value ? std::to_string(*goal.value) : std::string("absent")) << " "
              << (goal.passed ? "met"
                              : "NOT met" + (goal.reason.empty() ? "" : " (" + goal.reason + ")"))
              << "\n";
  }
}

/// How the run ended and the exit status that says so. Precedence: a signal over a device fault
/// over a failed behaviour over a failed goal.
RunOutcome outcome_of(const MainJobResult& result, bool goal_failed) {
  if (result.stopped_by_signal) {
    const int signal_number = stop_signal_number();
    return {"interrupted", exit_status_for_signal(signal_number),
            signal_number == SIGINT    ? "SIGINT"
            : signal_number == SIGHUP  ? "SIGHUP"
            : signal_number == SIGTERM ? "SIGTERM"
                                       : "signal " + std::to_string(signal_number)};
  }
  if (result.fault_latched_at_end) return {"device_fault", kExitDeviceFault, ""};
  // A behaviour that threw stopped itself and the robot held: the run did not do its task.
  if (result.behaviour && result.behaviour->failed) return {"behaviour_failed", kExitFailure, ""};
  if (goal_failed) return {"goal_failed", kExitFailure, ""};
  return {"completed", kExitOk, ""};
}

}  // namespace

int run_run_command(std::span<const std::string> args) {
  ArgumentParser parser("run", "EXPERIMENT.yaml [--set KEY=VALUE]... [--out DIR]");
  parser.positional("EXPERIMENT.yaml", "the experiment to run (firmware_config/experiments/)")
      .repeated_option("set", "KEY=VALUE",
                       "override an experiment key (experiment.duration_s=2) or, prefixed with "
                       "rig., a rig key (rig.loops.control.rate_hz=100)")
      .option("out", "DIR", "write each camera's last frame (PNG) and summary.json here")
      .option("can-log", "FILE",
              "log every CAN frame of the socketcan groups' buses to FILE in candump -L format "
              "(replay with canplayer -I FILE); written beside FILE and put in place when the "
              "run ends, so a run that never starts leaves FILE as it was (its frames in "
              "FILE.incomplete)");
  if (!parser.parse(args)) return kExitOk;
  // First: building configures the drives (SDO on a CAN rig), and a signal then must be heard,
  // never kill the program silently.
  const auto& stop = install_stop_signal_handlers();

  std::vector<config::ConfigOverride> overrides;
  config::ExperimentConfig experiment;
  try {
    for (const auto& text : parser.values("set")) overrides.push_back(config::parse_override(text));
    experiment = config::load_experiment(*parser.positional_value("EXPERIMENT.yaml"), overrides);
  } catch (const config::ConfigError& error) {
    report_config_error(error);
    return kExitBadInput;
  }

  // The destination is checked and claimed before any work: a bad --out fails at once.
  std::optional<OutputDirectory> out;
  if (parser.has("out")) out.emplace(parser.value("out"), "run");

  std::unique_ptr<can::CanTrafficLog> can_log;
  if (parser.has("can-log")) {
    try {
      can_log = std::make_unique<can::CanTrafficLog>(parser.value("can-log"));
    } catch (const std::runtime_error& error) {
      std::cerr << "cambio run: --can-log: " << error.what() << "\n";
      return kExitBadInput;
    }
  }

  hal::BackendFactory factory;
  std::unique_ptr<MainJob> job;
  try {
    register_builtin_backends(factory, experiment, can_log.get());
    job = std::make_unique<MainJob>(experiment, factory);
  } catch (const hal::BackendUnavailable& error) {
    std::cerr << "cambio run: " << error.what() << "\n";
    return kExitBadInput;
  } catch (const BehaviourSetupError& error) {
    std::cerr << "cambio run: " << error.what() << "\n";
    return kExitBadInput;
  } catch (const config::ConfigError& error) {
    report_config_error(error);
    return kExitBadInput;
  } catch (const std::runtime_error& error) {
    // A bus that cannot be opened, a drive that does not answer or refuses its parameters.
    std::cerr << "cambio run: " << error.what() << "\n";
    return kExitDeviceFault;
  }

  if (stop.load()) {
    // Nothing was activated: the drives are as the run found them (configured, not enabled).
    MainJobResult nothing_ran;
    nothing_ran.stopped_by_signal = true;
    const int signal_number = stop_signal_number();
    std::cerr << "cambio run: interrupted by " << outcome_of(nothing_ran, false).signal_name
              << " while starting: nothing ran, no drive was enabled, no results written\n";
    return exit_status_for_signal(signal_number);
  }
  std::cerr << "cambio run: " << experiment.name << " on rig '" << experiment.rig.name << "', "
            << (job->realtime() ? "realtime" : "lockstep") << " executor, " << experiment.duration_s
            << " s, seed " << experiment.seed << "\n";
  if (const auto renderer = job->renderer()) {
    std::cerr << "cambio run: renderer " << renderer->summary() << "\n";
  }
  if (job->realtime() && experiment.executor == config::ExecutorKind::kLockstep) {
    std::cerr << "cambio run: the rig drives real hardware: running on the realtime executor\n";
  }
  ProgressReporter progress("run", experiment.duration_s);
  const MainJobResult result =
      job->run(stop, [&](double done_s, double wall_s) { progress.update(done_s, wall_s); });
  progress.finish(result.simulated_s, result.wall_s);

  std::cout << runtime::format_statistics_table(result.loops.data(), result.loops.size());
  std::cout << runtime::format_wall_time_shares(
      runtime::wall_time_shares(result.loops.data(), result.loops.size(), result.wall_s),
      result.wall_s, !result.realtime);
  std::cout << "camera frames grabbed: " << result.camera_frames << " (" << result.stereo_pairs
            << " stereo pairs, " << result.mismatched_stereo_pairs
            << " refused for mismatched stamps)"
            << ", joint-loop holds: " << result.startup_hold_cycles
            << " cycles before the first targets, watchdog " << result.watchdog_cycles
            << " cycles, fault/stale holds: " << result.fault_hold_cycles << " cycles"
            << (result.fault_recoveries > 0
                    ? ", fault recoveries: " + std::to_string(result.fault_recoveries)
                    : "")
            << "\n";
  for (const auto& report : result.can_groups) {
    const auto& c = report.counters;
    std::cout << "CAN group " << report.group << ": " << c.syncs_sent << " SYNCs, "
              << c.tpdos_received << " TPDOs, " << c.missed_sync_answers << " missed answers, "
              << c.late_tpdos << " late TPDOs, " << c.emergencies << " EMCY, " << c.error_frames
              << " error frames, " << c.tx_queue_full << " frames refused by a full queue, "
              << c.malformed_frames + c.unexpected_frames << " malformed/unexpected frames\n";
  }
  if (result.fault_latched_at_end) {
    std::cout << "joint loop: a drive fault is latched; the joints hold until a fault reset\n";
  }
  if (result.perception) {
    const auto& d = result.perception->disparity;
    std::cout << "perception: " << result.perception->sequence << " stereo frames; disparity at "
              << "the fovea " << (d.valid ? std::to_string(d.disparity_px) + " px" : "invalid")
              << " (confidence " << d.confidence << ")\n";
  }
  if (result.behaviour) {
    const BehaviourReport& behaviour = *result.behaviour;
    std::cout << "behaviour " << behaviour.name << ": " << behaviour.steps << " steps; "
              << behaviour.status << "\n";
    if (behaviour.failed) std::cerr << "cambio run: behaviour stopped: " << behaviour.error << "\n";
  }
  bool goal_failed = false;
  std::optional<RunEvaluation> evaluation;
  if (const Trace* trace = job->trace()) {
    evaluation = evaluate_run(experiment, result, *trace);
    print_evaluation(*evaluation);
    goal_failed |= !all_passed(evaluation->goals);
  }
  for (const auto& loop : result.loops) {
    if (runtime::passes_allocation_gate(loop)) continue;
    std::cerr << "cambio run: warning: loop '" << loop.name << "' allocated " << loop.allocations
              << " times in update() without declaring it\n";
  }

  RunOutcome outcome = outcome_of(result, goal_failed);
  if (can_log) {
    const can::CanLogReport log = can_log->close();
    std::cerr << "cambio run: CAN log " << can_log->path() << ": " << log.records_written
              << " frames";
    if (log.records_dropped > 0)
      std::cerr << ", " << log.records_dropped << " LOST (writer fell behind)";
    std::cerr << (log.error.empty() ? "" : ", " + log.error) << "\n";
    // A log that misses frames is not the record the user asked for: the run says so.
    if (!log.ok() && outcome.exit_status == kExitOk) outcome = {"log_incomplete", kExitFailure, ""};
  }
  if (outcome.name == "interrupted") {
    std::cerr << "cambio run: interrupted by " << outcome.signal_name << " at "
              << result.simulated_s << " of " << experiment.duration_s << " s\n";
  } else if (outcome.name == "device_fault") {
    std::cerr << "cambio run: a device fault stopped the run (joints held since)\n";
  }
  if (out) {
    const auto frames = job->last_frames();
    for (std::size_t i = 0; i < frames.size(); ++i) {
      if (frames[i].sequence == 0) continue;
      out->stage(job->cameras()[i].name + ".png", encode_png(frames[i]));
    }
    if (const Trace* trace = job->trace()) {
      stage_trace(*out, *trace);
      PlotInputs plots;
      plots.title = experiment.name;
      plots.joints = job->head_joint_names();
      if (evaluation) {
        const auto saccade = evaluation->metrics.find("saccade_duration_s");
        const auto start = last_command_time(experiment, result, config::GazeAction::kSaccade);
        if (saccade && start) {
          plots.saccade_start_s = *start;
          plots.saccade_end_s = *start + *saccade;
        }
      }
      if (stop_hurried()) {
        std::cerr << "cambio run: plots skipped: a second signal asked to hurry\n";
      } else {
        stage_plots(*out, *trace, plots);
      }
    }
    out->stage("summary.json",
               json_text(summary_json(experiment, result, outcome, job->trace(), evaluation)));
    out->commit();
    std::cerr << "cambio run: wrote " << out->path().string() << " (" << out->files().size()
              << " files)\n";
  }
  if (stop.load() && !result.stopped_by_signal) {
    std::cerr << "cambio run: signal " << stop_signal_number()
              << " arrived after the run had ended; the results are complete\n";
  }
  return outcome.exit_status;
}

}  // namespace cambio::app
