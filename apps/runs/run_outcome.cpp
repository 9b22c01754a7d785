#include "run_outcome.hpp"

#include <csignal>
#include <iostream>

#include "command.hpp"
#include "stop_signal.hpp"

namespace cambio::app {

std::string stop_signal_name(int signal_number) {
  return signal_number == SIGINT    ? "SIGINT"
         : signal_number == SIGHUP  ? "SIGHUP"
         : signal_number == SIGTERM ? "SIGTERM"
                                    : "signal " + std::to_string(signal_number);
}

RunOutcome outcome_of(const MainJobResult& result, bool goal_failed, bool script_refused) {
  if (result.stopped_by_signal) {
    const int signal_number = stop_signal_number();
    return {"interrupted", exit_status_for_signal(signal_number), stop_signal_name(signal_number)};
  }
  if (result.fault_latched_at_end) return {"device_fault", kExitDeviceFault, ""};
  // A joint that stopped following its command while its drive said nothing: the controller
  // holding it held since, as after a device fault.
  if (result.tracking_fault()) return {"tracking_fault", kExitDeviceFault, ""};
  // A behaviour that threw stopped itself and the robot held: the run did not do its task.
  if (result.behaviour && result.behaviour->failed) return {"behaviour_failed", kExitFailure, ""};
  if (goal_failed) return {"goal_failed", kExitFailure, ""};
  if (script_refused) return {"commands_refused", kExitFailure, ""};
  return {"completed", kExitOk, ""};
}

bool report_refused_commands(const MainJobResult& result) {
  bool refused = false;
  if (result.gaze && result.gaze_rejected_commands > 0) {
    std::cerr << "cambio run: the gaze loop refused " << result.gaze_rejected_commands
              << " command(s), the last: " << control::to_string(result.gaze->last_refusal) << "\n";
    refused = true;
  }
  if (result.arms && !result.arms->refusal().empty()) {
    std::cerr << "cambio run: the arms refused a command: " << result.arms->refusal() << "\n";
    refused = true;
  }
  return refused;
}

void report_early_end(const RunOutcome& outcome, const MainJobResult& result, double duration_s) {
  if (outcome.name == "interrupted") {
    std::cerr << "cambio run: interrupted by " << outcome.signal_name << " at "
              << result.simulated_s << " of " << duration_s << " s\n";
  } else if (outcome.name == "device_fault") {
    for (const std::string& fault : result.camera_faults) {
      std::cerr << "cambio run: " << fault << "\n";
    }
    std::cerr << "cambio run: a device fault stopped the run (joints held since)\n";
  } else if (outcome.name == "tracking_fault") {
    for (const auto& report : result.tracking) {
      if (report.faulted) std::cerr << "cambio run: " << report.fault << " (held since)\n";
    }
  }
}

}  // namespace cambio::app
