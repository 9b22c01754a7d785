#include "experiment_run.hpp"

#include <iostream>
#include <memory>
#include <optional>
#include <stdexcept>

#include "builtin_backends.hpp"
#include "command.hpp"
#include "config_errors.hpp"
#include "main_job.hpp"
#include "progress_reporter.hpp"
#include "remote_commands.hpp"
#include "run_evaluation.hpp"
#include "run_outcome.hpp"
#include "run_report.hpp"
#include "run_results.hpp"
#include "stop_signal.hpp"

namespace cambio::app {

namespace {

/// The main job on the built-in backends; null (the reason printed, `exit_status` set) when a
/// backend, the behaviour or a device cannot be set up. Building configures the drives (SDO on a
/// CAN rig).
std::unique_ptr<MainJob> make_job_or_report(const config::ExperimentConfig& experiment,
                                            hal::BackendFactory& factory,
                                            can::CanTrafficLog* can_log, int& exit_status) {
  try {
    register_builtin_backends(factory, experiment, can_log);
    return std::make_unique<MainJob>(experiment, factory);
  } catch (const hal::BackendUnavailable& error) {
    std::cerr << "cambio run: " << error.what() << "\n";
    exit_status = kExitBadInput;
  } catch (const BehaviourSetupError& error) {
    std::cerr << "cambio run: " << error.what() << "\n";
    exit_status = kExitBadInput;
  } catch (const config::ConfigError& error) {
    report_config_error(error);
    exit_status = kExitBadInput;
  } catch (const std::runtime_error& error) {
    // A bus that cannot be opened, a drive that does not answer or refuses its parameters.
    std::cerr << "cambio run: " << error.what() << "\n";
    exit_status = kExitDeviceFault;
  }
  return nullptr;
}

/// Nothing was activated: the drives are as the run found them (configured, not enabled).
int report_stopped_while_starting() {
  const int signal_number = stop_signal_number();
  std::cerr << "cambio run: interrupted by " << stop_signal_name(signal_number)
            << " while starting: nothing ran, no drive was enabled, no results written\n";
  return exit_status_for_signal(signal_number);
}

void print_run_start(const config::ExperimentConfig& experiment, const MainJob& job) {
  std::cerr << "cambio run: " << experiment.name << " on rig '" << experiment.rig.name << "', "
            << (job.realtime() ? "realtime" : "lockstep") << " executor, " << experiment.duration_s
            << " s, seed " << experiment.seed << "\n";
  if (const auto renderer = job.renderer()) {
    std::cerr << "cambio run: renderer " << renderer->summary() << "\n";
  }
  if (job.realtime() && experiment.executor == config::ExecutorKind::kLockstep) {
    std::cerr << "cambio run: the rig drives real hardware: running on the realtime executor\n";
  }
}

MainJobResult run_with_progress(MainJob& job, const config::ExperimentConfig& experiment,
                                const std::atomic<bool>& stop) {
  ProgressReporter progress("run", experiment.duration_s);
  MainJobResult result =
      job.run(stop, [&](double done_s, double wall_s) { progress.update(done_s, wall_s); });
  progress.finish(result.simulated_s, result.wall_s);
  return result;
}

/// Closes the log and says what it holds. A log that misses frames is not the record the user
/// asked for: a run that otherwise completed says so in `outcome`.
void close_can_log(can::CanTrafficLog& can_log, RunOutcome& outcome) {
  const can::CanLogReport log = can_log.close();
  std::cerr << "cambio run: CAN log " << can_log.path() << ": " << log.records_written << " frames";
  if (log.records_dropped > 0)
    std::cerr << ", " << log.records_dropped << " LOST (writer fell behind)";
  std::cerr << (log.error.empty() ? "" : ", " + log.error) << "\n";
  if (!log.ok() && outcome.exit_status == kExitOk) outcome = {"log_incomplete", kExitFailure, ""};
}

}  // namespace

int run_experiment(const config::ExperimentConfig& experiment, can::CanTrafficLog* can_log,
                   OutputDirectory* out, const std::atomic<bool>& stop) {
  hal::BackendFactory factory;
  int exit_status = kExitOk;
  const std::unique_ptr<MainJob> job =
      make_job_or_report(experiment, factory, can_log, exit_status);
  if (!job) return exit_status;
  if (stop.load()) return report_stopped_while_starting();
  // Console lines from ROS 2, when the run takes its commands from there.
  std::unique_ptr<RemoteCommands> remote;
  if (job->actions() != nullptr && experiment.ros2 && experiment.ros2->commands) {
    remote = std::make_unique<RemoteCommands>(*job, experiment);
    (void)job->set_remote_command_handler(
        [remote = remote.get()](const std::string& line) { return remote->carry_out(line); });
  }

  print_run_start(experiment, *job);
  MainJobResult result;
  try {
    result = run_with_progress(*job, experiment, stop);
  } catch (const std::runtime_error& error) {
    // Starting the devices failed (a joint's homing at activate): nothing ran.
    std::cerr << "\ncambio run: " << error.what() << "\n";
    return kExitDeviceFault;
  }
  print_run_report(result);
  std::optional<RunEvaluation> evaluation;
  if (const Trace* trace = job->trace()) {
    evaluation = evaluate_run(experiment, result, *trace);
    print_evaluation(*evaluation);
  }
  warn_allocating_loops(result);

  // An experiment with goals is judged by them; one without is judged by its script, so a
  // command the loops refused is no completed run (the refusal was only in summary.json).
  const bool refused = report_refused_commands(result);
  const bool judged_by_script = experiment.goals.empty() && !experiment.behaviour;
  RunOutcome outcome =
      outcome_of(result, evaluation && !all_passed(evaluation->goals), refused && judged_by_script);
  if (can_log != nullptr) close_can_log(*can_log, outcome);
  report_early_end(outcome, result, experiment.duration_s);
  if (out != nullptr) write_run_results(*out, experiment, *job, result, outcome, evaluation);
  if (stop.load() && !result.stopped_by_signal) {
    std::cerr << "cambio run: signal " << stop_signal_number()
              << " arrived after the run had ended; the results are complete\n";
  }
  return outcome.exit_status;
}

}  // namespace cambio::app
