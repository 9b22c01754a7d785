#include "console_run.hpp"

#include <unistd.h>

#include <iostream>
#include <memory>
#include <new>
#include <optional>

#include "builtin_backends.hpp"
#include "command.hpp"
#include "config_errors.hpp"
#include "console_executors.hpp"
#include "remote_commands.hpp"
#include "stop_signal.hpp"

namespace cambio::app {

namespace {

/// The main job on the built-in backends; null (the reason printed, `exit_status` set) when a
/// backend or device cannot be set up or the experiment's task is not gaze.
std::unique_ptr<MainJob> make_job_or_report(const config::ExperimentConfig& experiment,
                                            hal::BackendFactory& factory, int& exit_status) {
  std::unique_ptr<MainJob> job;
  try {
    register_builtin_backends(factory, experiment, nullptr);
    // The console commands the gaze loop itself and evaluates nothing.
    job = std::make_unique<MainJob>(experiment, factory,
                                    MainJobOptions{.send_script = false, .record_trace = false});
  } catch (const hal::BackendUnavailable& error) {
    std::cerr << "cambio console: " << error.what() << "\n";
    exit_status = kExitBadInput;
    return nullptr;
  } catch (const config::ConfigError& error) {
    report_config_error(error);
    exit_status = kExitBadInput;
    return nullptr;
  } catch (const std::runtime_error& error) {
    std::cerr << "cambio console: " << error.what() << "\n";
    exit_status = kExitDeviceFault;
    return nullptr;
  }
  if (job->actions() == nullptr) {
    std::cerr << "cambio console: " << experiment.name
              << ": the console drives the gaze task; this experiment's task is not gaze\n";
    exit_status = kExitBadInput;
    return nullptr;
  }
  return job;
}

void print_console_start(const config::ExperimentConfig& experiment, const MainJob& job,
                         double real_time_factor, bool interactive) {
  std::cerr << "cambio console: " << experiment.name << " on rig '" << experiment.rig.name << "', "
            << (job.realtime() ? "realtime executor" : "lockstep executor");
  if (!job.realtime() && real_time_factor > 0.0) {
    std::cerr << " at " << real_time_factor << "x real time";
  } else if (!job.realtime()) {
    std::cerr << " as fast as the loops go";
  }
  std::cerr << (interactive ? "; type help for the commands, quit to stop\n" : "\n");
}

/// The loops' statistics and what the session refused; the exit status: a signal over a device
/// fault over a controller's tracking fault over refused input.
int report_console_end(const MainJobResult& result, const ConsoleSession& session,
                       const LineSource& lines) {
  std::cout << runtime::format_statistics_table(result.loops.data(), result.loops.size());
  std::cerr << "cambio console: ran " << result.simulated_s << " s (" << session.lines_refused()
            << " lines refused)\n";
  if (result.stopped_by_signal) return exit_status_for_signal(stop_signal_number());
  if (result.fault_latched_at_end) {
    std::cerr << "cambio console: a device fault stopped the robot (joints held since)\n";
    return kExitDeviceFault;
  }
  for (const auto& report : result.tracking) {
    if (!report.faulted) continue;
    std::cerr << "cambio console: " << report.fault << " (held since)\n";
    return kExitDeviceFault;
  }
  return lines.input_refused() ? kExitBadInput : kExitOk;
}

}  // namespace

namespace {

int run_session(const config::ExperimentConfig& experiment, double real_time_factor,
                std::optional<std::vector<std::string>> script) {
  hal::BackendFactory factory;
  int exit_status = kExitOk;
  const std::unique_ptr<MainJob> job = make_job_or_report(experiment, factory, exit_status);
  if (!job) return exit_status;
  ConsoleSession session(*job, *job->actions(), scene_object_names(experiment), std::cout);
  session.enable_capture();

  const bool interactive = !script && isatty(STDIN_FILENO) != 0;
  print_console_start(experiment, *job, real_time_factor, interactive);
  const auto& stop = install_stop_signal_handlers();
  LineSource lines = script ? LineSource(std::move(*script)) : LineSource(interactive);
  ConsoleRun run{*job, session, lines, stop, real_time_factor};
  MainJobResult result;
  try {
    result = job->realtime() ? run_console_realtime(run) : run_console_lockstep(run);
  } catch (const std::bad_alloc&) {
    throw;  // Said as running out of memory (main), not as a device's fault.
  } catch (const std::exception& error) {
    std::cerr << "cambio console: " << error.what() << "\n";
    return kExitDeviceFault;
  }
  const int status = report_console_end(result, session, lines);
  if (status == kExitOk && script && session.lines_refused() > 0) return kExitBadInput;
  return status;
}

}  // namespace

int run_console(const config::ExperimentConfig& experiment, double real_time_factor) {
  return run_session(experiment, real_time_factor, std::nullopt);
}

int run_console_script(const config::ExperimentConfig& experiment,
                       std::vector<std::string> script) {
  return run_session(experiment, 0.0, std::move(script));
}

}  // namespace cambio::app
