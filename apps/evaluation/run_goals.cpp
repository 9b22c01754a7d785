// The experiment's goals checked against a run's metrics (run_metrics.hpp: evaluate_goals,
// all_passed, goals_json).

#include <algorithm>
#include <cmath>

#include "run_metrics.hpp"

namespace cambio::app {

std::vector<GoalResult> evaluate_goals(const RunMetrics& metrics, std::span<const Goal> goals) {
  std::vector<GoalResult> results;
  for (const Goal& goal : goals) {
    GoalResult result;
    result.goal = goal;
    result.value = metrics.find(goal.metric);
    const bool is_max = goal.bound == GoalBound::kMax;
    if (!result.value) {
      const std::string why = metrics.absent_reason(goal.metric);
      result.reason = "absent: " + (why.empty() ? std::string("no such metric") : why);
    } else if (!std::isfinite(*result.value)) {
      result.reason = "the value is not finite";
    } else if (is_max ? *result.value <= goal.value : *result.value >= goal.value) {
      result.passed = true;
    } else {
      result.reason = is_max ? "above the maximum" : "below the minimum";
    }
    results.push_back(std::move(result));
  }
  return results;
}

bool all_passed(std::span<const GoalResult> results) {
  return std::all_of(results.begin(), results.end(),
                     [](const GoalResult& result) { return result.passed; });
}

Json goals_json(std::span<const GoalResult> results) {
  Json json = Json::object();
  for (const GoalResult& result : results) {
    Json& entry = json[result.goal.metric];
    const bool first = !entry.contains("passed");
    entry[result.goal.bound == GoalBound::kMax ? "max" : "min"] = result.goal.value;
    entry["value"] = result.value ? Json(*result.value) : Json(nullptr);
    entry["passed"] = (first || entry["passed"].get<bool>()) && result.passed;
    if (!result.reason.empty()) {
      entry["reason"] = entry.contains("reason")
                            ? entry["reason"].get<std::string>() + "; " + result.reason
                            : result.reason;
    }
  }
  return json;
}

}  // namespace cambio::app
