// `cambio gaze-bench [--scenes N] [--seed S] [--tasks LIST] [--jobs J] [--perception FILE]
// [--keep-failures DIR] [--json]`: the gaze behaviour on scenes nobody shipped. N runs per task
// are generated from the seed (gaze_scene_generator.hpp), each run in lockstep in a child process
// of its own (J at a time: runs are independent, and a run's renderer and GL state stay in its
// process), scored against the simulator's ground truth (gaze_bench_score.hpp). Prints per task
// the success rate, times and errors, and the disparity confidence's calibration.
#include <fcntl.h>
#include <poll.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>
#include <optional>
#include <string>
#include <thread>
#include <vector>

#include "argument_parser.hpp"
#include "builtin_backends.hpp"
#include "cambio/config/echoed_text.hpp"
#include "cambio/config/experiment_config.hpp"
#include "cambio/config/shipped_config.hpp"
#include "command.hpp"
#include "config_errors.hpp"
#include "gaze_bench_score.hpp"
#include "gaze_scene_generator.hpp"
#include "json_output.hpp"
#include "main_job.hpp"
#include "stop_signal.hpp"

namespace cambio::app {

namespace {

namespace fs = std::filesystem;

std::optional<double> from_json(const Json& json, const char* key) {
  if (!json.contains(key) || json[key].is_null()) return std::nullopt;
  return json[key].get<double>();
}

Json to_json(const std::optional<double>& value) {
  return value ? Json(*value) : Json(nullptr);
}

/// The score of one run as the child sends it to the parent.
Json score_json(const GeneratedGazeRun& run, const GazeRunScore& score) {
  Json calibration = Json::array();
  for (const auto& sample : score.calibration) {
    calibration.push_back(Json::array({sample.confidence, sample.right ? 1 : 0}));
  }
  return Json{{"name", run.name},
              {"task", std::string(task_name(run.task))},
              {"success", score.success},
              {"failure", score.failure},
              {"depth_m", run.target_depth_m},
              {"azimuth_deg", run.target_azimuth_deg},
              {"elevation_deg", run.target_elevation_deg},
              {"second_depth_m", run.second_depth_m},
              {"pursuit_speed_deg_s", run.pursuit_speed_deg_s},
              {"distractors", run.distractors},
              {"verged_at_s", to_json(score.verged_at_s)},
              {"first_verged_s", to_json(score.first_verged_s)},
              {"final_error_deg", to_json(score.final_error_deg)},
              {"worst_error_deg", to_json(score.worst_error_deg)},
              {"off_target_s", score.off_target_s},
              {"occluded_s", score.occluded_s},
              {"pursuit_rms_deg", to_json(score.pursuit_rms_deg)},
              {"calibration", calibration}};
}

/// Writes the run's two files into `directory` and returns the experiment file's path.
fs::path write_run_files(const GeneratedGazeRun& run, const fs::path& directory) {
  const auto write = [](const fs::path& path, const std::string& text) {
    std::ofstream file(path);
    file << text;
    file.close();
    if (!file) throw std::runtime_error("cannot write " + path.string());
  };
  write(directory / (run.name + ".scene.yaml"), run.scene_yaml);
  const fs::path experiment = directory / (run.name + ".yaml");
  write(experiment, run.experiment_yaml);
  return experiment;
}

/// In the child: runs and scores one generated run, returns its JSON (or an error object).
Json run_one(const GeneratedGazeRun& run, const fs::path& scratch) {
  try {
    const fs::path experiment_file = write_run_files(run, scratch);
    const config::ExperimentConfig experiment = config::load_experiment(experiment_file.string());
    hal::BackendFactory factory;
    register_builtin_backends(factory, experiment);
    MainJob job(experiment, factory);
    const std::atomic<bool> never{false};
    (void)job.run(never, [](double, double) {});
    if (job.trace() == nullptr) throw std::runtime_error("the run recorded no trace");
    return score_json(run, score_gaze_run(run, *job.trace()));
  } catch (const std::exception& error) {
    return Json{
        {"name", run.name}, {"task", std::string(task_name(run.task))}, {"error", error.what()}};
  }
}

struct Child {
  pid_t pid = -1;
  int fd = -1;
  std::size_t run = 0;
  std::string output;
};

/// Runs every run in a child process, `jobs` at a time; calls `done(run index, json)` as each
/// ends. A child that dies gives an error object.
void run_all(const std::vector<GeneratedGazeRun>& runs, int jobs, const fs::path& scratch,
             const std::atomic<bool>& stop, const std::function<void(std::size_t, Json)>& done) {
  std::vector<Child> children;
  std::size_t next = 0;
  while ((next < runs.size() && !stop) || !children.empty()) {
    while (next < runs.size() && !stop && static_cast<int>(children.size()) < jobs) {
      int pipe_fds[2];
      if (::pipe2(pipe_fds, O_CLOEXEC) != 0) throw std::runtime_error("pipe failed");
      std::fflush(nullptr);
      const pid_t pid = ::fork();
      if (pid < 0) throw std::runtime_error("fork failed");
      if (pid == 0) {
        ::close(pipe_fds[0]);
        const std::string text = run_one(runs[next], scratch).dump();
        std::size_t written = 0;
        while (written < text.size()) {
          const ssize_t n = ::write(pipe_fds[1], text.data() + written, text.size() - written);
          if (n < 0 && errno == EINTR) continue;
          if (n <= 0) ::_exit(1);
          written += static_cast<std::size_t>(n);
        }
        ::_exit(0);
      }
      ::close(pipe_fds[1]);
      children.push_back({pid, pipe_fds[0], next, {}});
      ++next;
    }
    std::vector<pollfd> fds;
    for (const Child& child : children) fds.push_back({child.fd, POLLIN, 0});
    if (::poll(fds.data(), fds.size(), 200) < 0 && errno != EINTR) {
      throw std::runtime_error("poll failed");
    }
    for (std::size_t k = 0; k < children.size();) {
      Child& child = children[k];
      char buffer[65536];
      const ssize_t n =
          (fds[k].revents & (POLLIN | POLLHUP)) != 0 ? ::read(child.fd, buffer, sizeof buffer) : -2;
      if (n > 0) child.output.append(buffer, static_cast<std::size_t>(n));
      if (n == 0 || (n == -1 && errno != EINTR && errno != EAGAIN)) {
        ::close(child.fd);
        int status = 0;
        while (::waitpid(child.pid, &status, 0) < 0 && errno == EINTR) {
        }
        Json result = Json::parse(child.output, nullptr, false);
        if (result.is_discarded() || !result.is_object()) {
          result = Json{{"name", runs[child.run].name},
                        {"task", std::string(task_name(runs[child.run].task))},
                        {"error", "the run's process ended with status " + std::to_string(status) +
                                      " and no result"}};
        }
        done(child.run, std::move(result));
        fds.erase(fds.begin() + static_cast<std::ptrdiff_t>(k));
        children.erase(children.begin() + static_cast<std::ptrdiff_t>(k));
        continue;
      }
      ++k;
    }
  }
}

double median(std::vector<double> values) {
  if (values.empty()) return std::nan("");
  std::sort(values.begin(), values.end());
  const std::size_t n = values.size();
  return n % 2 == 1 ? values[n / 2] : 0.5 * (values[n / 2 - 1] + values[n / 2]);
}

double quantile(std::vector<double> values, double q) {
  if (values.empty()) return std::nan("");
  std::sort(values.begin(), values.end());
  return values[static_cast<std::size_t>(std::lround(q * static_cast<double>(values.size() - 1)))];
}

Json number_or_null(double value) {
  return std::isfinite(value) ? Json(value) : Json(nullptr);
}

/// Per task: the rates and figures; overall: the calibration table.
Json summarise(const std::vector<Json>& results, std::uint64_t seed, int scenes) {
  Json tasks = Json::object();
  std::array<int, 10> bin_count{};
  std::array<int, 10> bin_right{};
  for (const GazeBenchTask task : kGazeBenchTasks) {
    const std::string name(task_name(task));
    int runs = 0, successes = 0, errors = 0;
    std::vector<double> verged, final_error, worst, off_target, occluded, rms;
    Json failures = Json::array();
    for (const Json& r : results) {
      if (r.value("task", "") != name) continue;
      ++runs;
      if (r.contains("error")) {
        ++errors;
        failures.push_back(Json{{"name", r["name"]}, {"why", r["error"]}});
        continue;
      }
      if (r["success"].get<bool>()) {
        ++successes;
      } else {
        failures.push_back(Json{{"name", r["name"]}, {"why", r["failure"]}});
      }
      if (auto v = from_json(r, "verged_at_s")) verged.push_back(*v);
      if (auto v = from_json(r, "final_error_deg")) final_error.push_back(*v);
      if (auto v = from_json(r, "worst_error_deg")) worst.push_back(*v);
      if (auto v = from_json(r, "pursuit_rms_deg")) rms.push_back(*v);
      off_target.push_back(r["off_target_s"].get<double>());
      occluded.push_back(r["occluded_s"].get<double>());
      for (const Json& sample : r["calibration"]) {
        const double c = sample[0].get<double>();
        const auto bin = static_cast<std::size_t>(std::clamp(static_cast<int>(c * 10.0), 0, 9));
        ++bin_count[bin];
        bin_right[bin] += sample[1].get<int>();
      }
    }
    if (runs == 0) continue;
    Json t{{"runs", runs},
           {"successes", successes},
           {"success_rate", static_cast<double>(successes) / runs},
           {"errors", errors},
           {"median_time_to_verge_s", number_or_null(median(verged))},
           {"p95_time_to_verge_s", number_or_null(quantile(verged, 0.95))},
           {"median_final_error_deg", number_or_null(median(final_error))},
           {"p95_final_error_deg", number_or_null(quantile(final_error, 0.95))},
           {"worst_error_deg", number_or_null(quantile(worst, 1.0))},
           {"median_off_target_s", number_or_null(median(off_target))},
           {"max_off_target_s", number_or_null(quantile(off_target, 1.0))},
           {"total_occluded_s", [&] {
              double s = 0.0;
              for (double v : occluded) s += v;
              return s;
            }()}};
    if (!rms.empty()) {
      t["median_pursuit_rms_deg"] = median(rms);
      t["max_pursuit_rms_deg"] = quantile(rms, 1.0);
    }
    t["failures"] = failures;
    tasks[name] = t;
  }
  Json calibration = Json::array();
  for (std::size_t b = 0; b < bin_count.size(); ++b) {
    calibration.push_back(Json{
        {"confidence_from", b / 10.0},
        {"confidence_to", (b + 1) / 10.0},
        {"measurements", bin_count[b]},
        {"right_fraction", bin_count[b] > 0 ? Json(static_cast<double>(bin_right[b]) / bin_count[b])
                                            : Json(nullptr)}});
  }
  return Json{{"seed", seed},
              {"scenes_per_task", scenes},
              {"tasks", tasks},
              {"confidence_calibration", calibration}};
}

void print_table(const Json& summary) {
  std::printf("cambio gaze-bench: seed %llu, %d scenes per task, scored against the sim's truth\n",
              static_cast<unsigned long long>(summary["seed"].get<std::uint64_t>()),
              summary["scenes_per_task"].get<int>());
  std::printf("%-14s %6s %8s %10s %10s %10s %10s\n", "task", "runs", "success", "verge_s",
              "final_deg", "p95_deg", "off_s_max");
  for (const auto& [name, t] : summary["tasks"].items()) {
    const auto cell = [&](const char* key) {
      return t[key].is_null() ? std::nan("") : t[key].get<double>();
    };
    std::printf("%-14s %6d %7.1f%% %10.3f %10.3f %10.3f %10.3f\n", name.c_str(),
                t["runs"].get<int>(), 100.0 * t["success_rate"].get<double>(),
                cell("median_time_to_verge_s"), cell("median_final_error_deg"),
                cell("p95_final_error_deg"), cell("max_off_target_s"));
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

std::vector<GazeBenchTask> parse_tasks(const std::string& list) {
  std::vector<GazeBenchTask> tasks;
  std::size_t start = 0;
  while (start <= list.size()) {
    const std::size_t comma = std::min(list.find(',', start), list.size());
    const std::string name = list.substr(start, comma - start);
    bool found = false;
    for (const GazeBenchTask task : kGazeBenchTasks) {
      if (task_name(task) == name) {
        tasks.push_back(task);
        found = true;
      }
    }
    if (!found) {
      std::string known;
      for (const GazeBenchTask task : kGazeBenchTasks) known += " " + std::string(task_name(task));
      throw UsageError("--tasks: '" + config::echoed(name) + "' is not a task (tasks:" + known +
                       ")");
    }
    start = comma + 1;
  }
  return tasks;
}

}  // namespace

int run_gaze_bench_command(std::span<const std::string> args) {
  ArgumentParser parser("gaze-bench",
                        "[--scenes N] [--seed S] [--tasks verge,saccade_depth,...] [--jobs J] "
                        "[--perception FILE] [--keep-failures DIR] [--json]");
  parser.option("scenes", "N", "generated scenes per task (default 20)")
      .option("seed", "S", "the generator's seed (default 1)")
      .option("tasks", "LIST",
              "comma-separated tasks: verge, saccade_depth, distractors, pursuit, untextured "
              "(default all)")
      .option("jobs", "J", "runs at once, each in a process of its own (default: the cores)")
      .option("perception", "FILE", "the SSM settings the runs use (default: the shipped ones)")
      .option("keep-failures", "DIR",
              "write each failed run's experiment and scene files there, to replay with "
              "`cambio run`")
      .flag("json", "print one JSON object: per task and per run, and the calibration");
  if (!parser.parse(args)) return kExitOk;
  const int scenes = static_cast<int>(parser.integer("scenes", 20, config::Range::closed(1, 10'000),
                                                     "a run takes seconds; 10000 take hours"));
  const auto seed = static_cast<std::uint64_t>(
      parser.integer("seed", 1, config::Range::closed(0, 4'000'000'000LL), "a 32-bit seed"));
  const int jobs =
      static_cast<int>(parser.integer("jobs", std::max(1u, std::thread::hardware_concurrency()),
                                      config::Range::closed(1, 256), "one process per run"));
  const std::vector<GazeBenchTask> tasks =
      parser.has("tasks")
          ? parse_tasks(parser.value("tasks"))
          : std::vector<GazeBenchTask>(kGazeBenchTasks.begin(), kGazeBenchTasks.end());
  std::string perception;
  if (parser.has("perception")) {
    perception = fs::absolute(parser.value("perception")).string();
    if (!fs::is_regular_file(perception)) {
      throw UsageError("--perception '" + config::echoed(parser.value("perception")) +
                       "': not a readable file");
    }
  } else {
    perception = config::find_shipped_config("perception/vergence.yaml");
  }
  const std::string rig = config::find_shipped_config("rigs/cambio.yaml");
  std::optional<fs::path> keep;
  if (parser.has("keep-failures")) {
    keep = fs::path(parser.value("keep-failures"));
    std::error_code error;
    fs::create_directories(*keep, error);
    if (error || !fs::is_directory(*keep)) {
      throw UsageError("--keep-failures '" + config::echoed(keep->string()) +
                       "': cannot create it");
    }
  }

  const HeadGeometry head;
  std::vector<GeneratedGazeRun> runs;
  for (const GazeBenchTask task : tasks) {
    for (int k = 0; k < scenes; ++k) {
      runs.push_back(generate_gaze_run(task, k, seed, head, rig, perception));
    }
  }

  char scratch_template[] = "/tmp/cambio-gaze-bench-XXXXXX";
  if (::mkdtemp(scratch_template) == nullptr)
    throw std::runtime_error("cannot make a scratch folder");
  const fs::path scratch(scratch_template);
  const std::atomic<bool>& stop = install_stop_signal_handlers();
  std::vector<Json> results(runs.size());
  std::size_t finished = 0;
  const bool terminal = ::isatty(STDERR_FILENO) != 0;
  run_all(runs, jobs, scratch, stop, [&](std::size_t index, Json result) {
    results[index] = std::move(result);
    ++finished;
    const int width = 30;
    const int filled = static_cast<int>(width * finished / runs.size());
    std::fprintf(stderr, "%sgaze-bench [%s%s] %zu/%zu %s%s", terminal ? "\r" : "",
                 std::string(static_cast<std::size_t>(filled), '#').c_str(),
                 std::string(static_cast<std::size_t>(width - filled), '.').c_str(), finished,
                 runs.size(), runs[index].name.c_str(), terminal ? "   " : "\n");
  });
  if (terminal) std::fprintf(stderr, "\n");
  std::error_code ignored;
  fs::remove_all(scratch, ignored);

  std::vector<Json> done;
  for (std::size_t k = 0; k < runs.size(); ++k) {
    if (results[k].is_null()) continue;
    if (keep && (results[k].contains("error") || !results[k].value("success", false))) {
      (void)write_run_files(runs[k], *keep);
    }
    done.push_back(results[k]);
  }
  Json summary = summarise(done, seed, scenes);
  if (parser.flag_set("json")) {
    summary["runs"] = done;
    std::printf("%s\n", json_text(summary).c_str());
  } else {
    print_table(summary);
  }
  if (stop) {
    std::fprintf(stderr, "gaze-bench: stopped by a signal after %zu of %zu runs\n", finished,
                 runs.size());
    return 128 + stop_signal_number();
  }
  return kExitOk;
}

}  // namespace cambio::app
