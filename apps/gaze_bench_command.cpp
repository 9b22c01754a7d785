// `cambio gaze-bench [--scenes N] [--seed S] [--tasks LIST] [--jobs J] [--perception FILE]
// [--keep-failures DIR] [--json]`: the gaze behaviour on scenes nobody shipped. N runs per task
// are generated from the seed (gaze_scene_generator.hpp), each run in lockstep in a child process
// of its own (J at a time: runs are independent, and a run's renderer and GL state stay in its
// process), scored against the simulator's ground truth (gaze_bench_score.hpp). Prints per task
// the success rate, times and errors, and the disparity confidence's calibration. The bench is in
// benchmarks/gaze_bench.hpp.
#include <algorithm>
#include <filesystem>
#include <optional>
#include <string>
#include <thread>
#include <vector>

#include "argument_parser.hpp"
#include "cambio/config/echoed_text.hpp"
#include "cambio/config/shipped_config.hpp"
#include "command.hpp"
#include "gaze_bench.hpp"

namespace cambio::app {

namespace {

namespace fs = std::filesystem;

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

/// --perception as an absolute path (a child's experiment file names it), or the shipped one.
std::string perception_path(const ArgumentParser& parser) {
  if (!parser.has("perception")) return config::find_shipped_config("perception/vergence.yaml");
  const std::string perception = fs::absolute(parser.value("perception")).string();
  if (!fs::is_regular_file(perception)) {
    throw UsageError("--perception '" + config::echoed(parser.value("perception")) +
                     "': not a readable file");
  }
  return perception;
}

/// --keep-failures, created.
std::optional<fs::path> keep_failures_directory(const ArgumentParser& parser) {
  if (!parser.has("keep-failures")) return std::nullopt;
  fs::path keep(parser.value("keep-failures"));
  std::error_code error;
  fs::create_directories(keep, error);
  if (error || !fs::is_directory(keep)) {
    throw UsageError("--keep-failures '" + config::echoed(keep.string()) + "': cannot create it");
  }
  return keep;
}

GazeBenchOptions gaze_bench_options(const ArgumentParser& parser) {
  GazeBenchOptions options;
  options.scenes = static_cast<int>(parser.integer("scenes", 20, config::Range::closed(1, 10'000),
                                                   "a run takes seconds; 10000 take hours"));
  options.seed = static_cast<std::uint64_t>(
      parser.integer("seed", 1, config::Range::closed(0, 4'000'000'000LL), "a 32-bit seed"));
  options.jobs =
      static_cast<int>(parser.integer("jobs", std::max(1u, std::thread::hardware_concurrency()),
                                      config::Range::closed(1, 256), "one process per run"));
  options.tasks = parser.has("tasks")
                      ? parse_tasks(parser.value("tasks"))
                      : std::vector<GazeBenchTask>(kGazeBenchTasks.begin(), kGazeBenchTasks.end());
  options.perception_path = perception_path(parser);
  options.rig_path = config::find_shipped_config("rigs/cambio.yaml");
  options.keep_failures = keep_failures_directory(parser);
  options.json = parser.flag_set("json");
  return options;
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
  return run_gaze_bench(gaze_bench_options(parser));
}

}  // namespace cambio::app
