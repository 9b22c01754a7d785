#pragma once

// What a `cambio run`'s trace says about the run: its metrics and the experiment's goals on them.

#include <optional>
#include <vector>

#include "cambio/config/experiment_config.hpp"
#include "main_job_result.hpp"
#include "run_metrics.hpp"

namespace cambio::app {

struct RunEvaluation {
  RunMetrics metrics;
  std::vector<GoalResult> goals;
};

/// The metrics of `trace`, from the scripted gaze commands the run sent, and the experiment's
/// goals judged on them.
RunEvaluation evaluate_run(const config::ExperimentConfig& experiment, const MainJobResult& result,
                           const Trace& trace);

/// The metrics on one line, then one line per goal, on stdout.
void print_evaluation(const RunEvaluation& evaluation);

/// When the scripted command of `action` last went out (s since the run's start), if it did.
std::optional<double> last_command_time(const config::ExperimentConfig& experiment,
                                        const MainJobResult& result, config::GazeAction action);

}  // namespace cambio::app
