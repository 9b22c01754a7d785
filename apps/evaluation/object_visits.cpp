// Which of the evaluation's visit_objects the dominant eye's axis rested on, and when
// (run_metrics.hpp: objects_visited, all_objects_visited_s).

#include <algorithm>
#include <string>

#include "metric_families.hpp"

namespace cambio::app {

std::vector<std::optional<double>> object_visit_times(const Trace& trace, double dwell_s) {
  std::vector<std::optional<double>> visits(trace.visit_objects.size());
  int resting_on = -1;  // The object of the current run of rows, -1 for none.
  double since_s = 0.0;
  for (const TraceRow& row : trace.rows) {
    const bool still = !(row.gaze_status && row.saccade_active);
    const int object = still ? row.axis_object : -1;
    if (object != resting_on) {
      resting_on = object;
      since_s = row.time_s;
    }
    if (object < 0 || object >= static_cast<int>(visits.size())) continue;
    auto& visit = visits[static_cast<std::size_t>(object)];
    // Row times are sums of periods: a dwell of whole periods may fall short by rounding.
    if (!visit && row.time_s - since_s >= dwell_s - 1e-9) visit = row.time_s;
  }
  return visits;
}

Json visits_json(const Trace& trace, double dwell_s) {
  Json json = Json::object();
  const auto visits = object_visit_times(trace, dwell_s);
  for (std::size_t i = 0; i < visits.size(); ++i) {
    json[trace.visit_objects[i]] = visits[i] ? Json(*visits[i]) : Json(nullptr);
  }
  return json;
}

namespace detail {

void visit_metrics(const ScoredTrace& scored, MetricsBuilder& out) {
  const Trace& trace = scored.trace;
  if (trace.visit_objects.empty()) {
    for (const char* name : {"objects_visited", "all_objects_visited_s"}) {
      out.absent(name, "the experiment names no evaluation.visit_objects");
    }
    return;
  }
  const auto visits = object_visit_times(trace, scored.inputs.visit_dwell_s);
  double visited = 0.0;
  double last_s = 0.0;
  std::string missed;
  for (std::size_t i = 0; i < visits.size(); ++i) {
    if (visits[i]) {
      visited += 1.0;
      last_s = std::max(last_s, *visits[i]);
    } else {
      missed += (missed.empty() ? "" : ", ") + trace.visit_objects[i];
    }
  }
  out.set("objects_visited", visited);
  if (missed.empty()) {
    out.set("all_objects_visited_s", last_s);
  } else {
    out.absent("all_objects_visited_s", "never visited: " + missed);
  }
}

}  // namespace detail

}  // namespace cambio::app
