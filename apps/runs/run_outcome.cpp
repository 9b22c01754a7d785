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

RunOutcome outcome_of(const MainJobResult& result, bool goal_failed) {
  if (result.stopped_by_signal) {
    const int signal_number = stop_signal_number();
    return {"interrupted", exit_status_for_signal(signal_number), stop_signal_name(signal_number)};
  }
  if (result.fault_latched_at_end) return {"device_fault", kExitDeviceFault, ""};
  // A behaviour that threw stopped itself and the robot held: the run did not do its task.
  if (result.behaviour && result.behaviour->failed) return {"behaviour_failed", kExitFailure, ""};
  if (goal_failed) return {"goal_failed", kExitFailure, ""};
  return {"completed", kExitOk, ""};
}

void report_early_end(const RunOutcome& outcome, const MainJobResult& result, double duration_s) {
  if (outcome.name == "interrupted") {
    std::cerr << "cambio run: interrupted by " << outcome.signal_name << " at "
              << result.simulated_s << " of " << duration_s << " s\n";
  } else if (outcome.name == "device_fault") {
    std::cerr << "cambio run: a device fault stopped the run (joints held since)\n";
  }
}

}  // namespace cambio::app
