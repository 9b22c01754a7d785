#include "gaze_bench_summary.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <map>
#include <optional>
#include <string>

#include "bench_timing.hpp"
#include "gaze_bench_score.hpp"
#include "gaze_scene_generator.hpp"

namespace cambio::app {

namespace {

/// Measurements per confidence bin of 0.1, and how many of them were right.
struct CalibrationBins {
  std::array<int, 10> count{};
  std::array<int, 10> right{};
};

std::optional<double> from_json(const Json& json, const char* key) {
  if (!json.contains(key) || json[key].is_null()) return std::nullopt;
  return json[key].get<double>();
}

/// NaN for none: the JSON says null, the table nan.
double median(std::vector<double> values) {
  if (values.empty()) return std::nan("");
  return median_of(std::move(values));
}

double quantile(std::vector<double> values, double q) {
  if (values.empty()) return std::nan("");
  std::sort(values.begin(), values.end());
  return values[static_cast<std::size_t>(std::lround(q * static_cast<double>(values.size() - 1)))];
}

/// A run spending longer than this off the target in one stretch was drawn onto another
/// surface: the distractors' goal (GazeScoreSettings::max_off_target_s), for every task.
const double kDrawnOffAfter_s = GazeScoreSettings{}.max_off_target_s;

Json number_or_null(double value) {
  return std::isfinite(value) ? Json(value) : Json(nullptr);
}

/// One task's runs, as the results give them.
struct TaskFigures {
  int runs = 0, successes = 0, errors = 0;
  std::vector<double> verged, final_error, worst, off_target, longest_off_target, occluded, rms;
  /// Runs and successes by the target's texture kind: what kinds of surface the vision fails on.
  std::map<std::string, std::array<int, 2>> by_texture;
  /// How the runs that did not meet the goal ended (each counted once, in this order): the
  /// verging eye never came within verged_deg of the target (it held, or stopped short); it
  /// verged, then spent longer than the distractors' bound off it in one stretch while the
  /// target was visible (drawn onto another surface); or it fell short otherwise (verged late,
  /// ended a little off; every failed pursuit: its RMS above its goal).
  int never_verged = 0, drawn_off = 0, short_of_goal = 0;
  Json failures = Json::array();
};

/// Gathers the results of task `name`; their calibration samples go into `bins`.
TaskFigures gather_task(const std::vector<Json>& results, const std::string& name,
                        CalibrationBins& bins) {
  TaskFigures f;
  for (const Json& r : results) {
    if (r.value("task", "") != name) continue;
    ++f.runs;
    if (r.contains("error")) {
      ++f.errors;
      f.failures.push_back(Json{{"name", r["name"]}, {"why", r["error"]}});
      continue;
    }
    auto& by_texture = f.by_texture[r.value("target_texture", "unknown")];
    ++by_texture[0];
    if (r["success"].get<bool>()) {
      ++f.successes;
      ++by_texture[1];
    } else {
      f.failures.push_back(Json{{"name", r["name"]}, {"why", r["failure"]}});
      if (from_json(r, "pursuit_rms_deg")) {
        ++f.short_of_goal;  // Pursuit is judged by the dominant eye's RMS error alone.
      } else if (!from_json(r, "first_verged_s")) {
        ++f.never_verged;
      } else if (r["longest_off_target_s"].get<double>() > kDrawnOffAfter_s) {
        ++f.drawn_off;
      } else {
        ++f.short_of_goal;
      }
    }
    if (auto v = from_json(r, "verged_at_s")) f.verged.push_back(*v);
    if (auto v = from_json(r, "final_error_deg")) f.final_error.push_back(*v);
    if (auto v = from_json(r, "worst_error_deg")) f.worst.push_back(*v);
    if (auto v = from_json(r, "pursuit_rms_deg")) f.rms.push_back(*v);
    f.off_target.push_back(r["off_target_s"].get<double>());
    f.longest_off_target.push_back(r["longest_off_target_s"].get<double>());
    f.occluded.push_back(r["occluded_s"].get<double>());
    for (const Json& sample : r["calibration"]) {
      const double c = sample[0].get<double>();
      const auto bin = static_cast<std::size_t>(std::clamp(static_cast<int>(c * 10.0), 0, 9));
      ++bins.count[bin];
      bins.right[bin] += sample[1].get<int>();
    }
  }
  return f;
}

Json task_json(const TaskFigures& f) {
  Json t{{"runs", f.runs},
         {"successes", f.successes},
         {"success_rate", static_cast<double>(f.successes) / f.runs},
         {"errors", f.errors},
         {"median_time_to_verge_s", number_or_null(median(f.verged))},
         {"p95_time_to_verge_s", number_or_null(quantile(f.verged, 0.95))},
         {"median_final_error_deg", number_or_null(median(f.final_error))},
         {"p95_final_error_deg", number_or_null(quantile(f.final_error, 0.95))},
         {"worst_error_deg", number_or_null(quantile(f.worst, 1.0))},
         {"median_off_target_s", number_or_null(median(f.off_target))},
         {"max_off_target_s", number_or_null(quantile(f.off_target, 1.0))},
         {"max_longest_off_target_s", number_or_null(quantile(f.longest_off_target, 1.0))},
         {"total_occluded_s", [&] {
            double s = 0.0;
            for (double v : f.occluded) s += v;
            return s;
          }()}};
  if (!f.rms.empty()) {
    t["median_pursuit_rms_deg"] = median(f.rms);
    t["max_pursuit_rms_deg"] = quantile(f.rms, 1.0);
  }
  Json by_texture = Json::object();
  for (const auto& [kind, counts] : f.by_texture) {
    by_texture[kind] = Json{{"runs", counts[0]}, {"successes", counts[1]}};
  }
  t["by_target_texture"] = by_texture;
  t["failed_runs"] = Json{{"never_verged", f.never_verged},
                          {"drawn_off_target", f.drawn_off},
                          {"short_of_goal", f.short_of_goal}};
  t["failures"] = f.failures;
  return t;
}

Json calibration_json(const CalibrationBins& bins) {
  Json calibration = Json::array();
  for (std::size_t b = 0; b < bins.count.size(); ++b) {
    calibration.push_back(
        Json{{"confidence_from", b / 10.0},
             {"confidence_to", (b + 1) / 10.0},
             {"measurements", bins.count[b]},
             {"right_fraction", bins.count[b] > 0
                                    ? Json(static_cast<double>(bins.right[b]) / bins.count[b])
                                    : Json(nullptr)}});
  }
  return calibration;
}

}  // namespace

Json summarise_gaze_bench(const std::vector<Json>& results, std::uint64_t seed, int scenes) {
  Json tasks = Json::object();
  CalibrationBins bins;
  for (const GazeBenchTask task : kGazeBenchTasks) {
    const std::string name(task_name(task));
    const TaskFigures figures = gather_task(results, name, bins);
    if (figures.runs == 0) continue;
    tasks[name] = task_json(figures);
  }
  return Json{{"seed", seed},
              {"scenes_per_task", scenes},
              {"tasks", tasks},
              {"confidence_calibration", calibration_json(bins)}};
}

void print_gaze_bench_table(const Json& summary) {
  std::printf("cambio gaze-bench: seed %llu, %d scenes per task, scored against the sim's truth\n",
              static_cast<unsigned long long>(summary["seed"].get<std::uint64_t>()),
              summary["scenes_per_task"].get<int>());
  std::printf("%-14s %6s %8s %10s %10s %10s %10s\n", "task", "runs", "success", "verge_s",
              "final_deg", "p95_deg", "off_s_max");
  for (const auto& task : summary["tasks"].items()) {
    // Named, not a structured binding: clang before 16 cannot capture one in a lambda.
    const std::string& name = task.key();
    const Json& t = task.value();
    const auto cell = [&](const char* key) {
      return t[key].is_null() ? std::nan("") : t[key].get<double>();
    };
    std::printf("%-14s %6d %7.1f%% %10.3f %10.3f %10.3f %10.3f\n", name.c_str(),
                t["runs"].get<int>(), 100.0 * t["success_rate"].get<double>(),
                cell("median_time_to_verge_s"), cell("median_final_error_deg"),
                cell("p95_final_error_deg"), cell("max_off_target_s"));
    std::string by_texture = "    by target texture:";
    for (const auto& kind : t["by_target_texture"].items()) {
      by_texture += " " + kind.key() + " " + std::to_string(kind.value()["successes"].get<int>()) +
                    "/" + std::to_string(kind.value()["runs"].get<int>());
    }
    std::printf("%s\n", by_texture.c_str());
    const Json& failed = t["failed_runs"];
    std::printf("    failed runs: %d never verged, %d drawn off the target, %d short of the goal\n",
                failed["never_verged"].get<int>(), failed["drawn_off_target"].get<int>(),
                failed["short_of_goal"].get<int>());
    for (const Json& f : t["failures"]) {
      std::printf("    %s: %s\n", f["name"].get<std::string>().c_str(),
                  f["why"].get<std::string>().c_str());
    }
  }
  std::printf("confidence calibration (measurements within 2 px of the truth):\n");
  for (const Json& bin : summary["confidence_calibration"]) {
    if (bin["measurements"].get<int>() == 0) continue;
    std::printf("  [%.1f, %.1f): %6d measurements, %5.1f%% right\n",
                bin["confidence_from"].get<double>(), bin["confidence_to"].get<double>(),
                bin["measurements"].get<int>(), 100.0 * bin["right_fraction"].get<double>());
  }
}

}  // namespace cambio::app
