#include "run_evaluation.hpp"

#include <iostream>
#include <numbers>
#include <string>

#include "controller_params.hpp"

namespace cambio::app {

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

}  // namespace cambio::app
