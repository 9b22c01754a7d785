#pragma once

// How a `cambio run` ended: the word summary.json gives it and the exit status that says so.

#include <string>

#include "main_job_result.hpp"

namespace cambio::app {

struct RunOutcome {
  /// completed, goal_failed, commands_refused, behaviour_failed, device_fault, tracking_fault,
  /// interrupted or log_incomplete.
  std::string name;
  int exit_status = 0;
  std::string signal_name;  ///< Set when a signal stopped the run.
};

/// How the run ended and the exit status that says so. Precedence: a signal over a device fault
/// over a controller's tracking fault (exit 3 too) over a failed behaviour over a failed goal
/// over a refused command of a goal-less script (`script_refused`: its experiment has neither
/// goals nor a behaviour, so carrying out its script is its whole task).
RunOutcome outcome_of(const MainJobResult& result, bool goal_failed, bool script_refused = false);

/// Says on stderr what the loops refused of the commands they were sent (the gaze loop's count
/// and last reason, the arms' last reason); true when they refused any.
bool report_refused_commands(const MainJobResult& result);

/// A stop signal as the messages name it: SIGINT, SIGHUP, SIGTERM or "signal N".
std::string stop_signal_name(int signal_number);

/// Says on stderr why an interrupted or faulted run ended early; nothing for other outcomes.
void report_early_end(const RunOutcome& outcome, const MainJobResult& result, double duration_s);

}  // namespace cambio::app
