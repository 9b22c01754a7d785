#include "gaze_bench.hpp"

#include <unistd.h>

#include <cstdio>
#include <cstdlib>
#include <stdexcept>

#include "command.hpp"
#include "gaze_bench_runs.hpp"
#include "gaze_bench_summary.hpp"
#include "json_output.hpp"
#include "stop_signal.hpp"

namespace cambio::app {

namespace {

namespace fs = std::filesystem;

std::vector<GeneratedGazeRun> generate_runs(const GazeBenchOptions& options) {
  const HeadGeometry head;
  std::vector<GeneratedGazeRun> runs;
  for (const GazeBenchTask task : options.tasks) {
    for (int k = 0; k < options.scenes; ++k) {
      runs.push_back(generate_gaze_run(task, k, options.seed, head, options.rig_path,
                                       options.perception_path));
    }
  }
  return runs;
}

/// A bar redrawn in place on a terminal; a line per finished run otherwise.
void print_progress(std::size_t finished, std::size_t total, const std::string& name,
                    bool terminal) {
  const int width = 30;
  const int filled = static_cast<int>(width * finished / total);
  std::fprintf(stderr, "%sgaze-bench [%s%s] %zu/%zu %s%s", terminal ? "\r" : "",
               std::string(static_cast<std::size_t>(filled), '#').c_str(),
               std::string(static_cast<std::size_t>(width - filled), '.').c_str(), finished, total,
               name.c_str(), terminal ? "   " : "\n");
}

fs::path make_scratch_folder() {
  char scratch_template[] = "/tmp/cambio-gaze-bench-XXXXXX";
  if (::mkdtemp(scratch_template) == nullptr)
    throw std::runtime_error("cannot make a scratch folder");
  return fs::path(scratch_template);
}

/// Each run's JSON at its index, null for those a stop signal kept from starting; `finished`
/// counts the runs that ended.
std::vector<Json> run_with_progress(const std::vector<GeneratedGazeRun>& runs, int jobs,
                                    const fs::path& scratch, const std::atomic<bool>& stop,
                                    std::size_t& finished) {
  std::vector<Json> results(runs.size());
  const bool terminal = ::isatty(STDERR_FILENO) != 0;
  run_in_child_processes(runs, jobs, scratch, stop, [&](std::size_t index, Json result) {
    results[index] = std::move(result);
    ++finished;
    print_progress(finished, runs.size(), runs[index].name, terminal);
  });
  if (terminal) std::fprintf(stderr, "\n");
  return results;
}

/// The results of the runs that ended, in run order; a failed run's files are written to
/// `keep_failures` when given.
std::vector<Json> finished_results(const std::vector<GeneratedGazeRun>& runs,
                                   const std::vector<Json>& results,
                                   const std::optional<fs::path>& keep_failures) {
  std::vector<Json> done;
  for (std::size_t k = 0; k < runs.size(); ++k) {
    if (results[k].is_null()) continue;
    if (keep_failures && (results[k].contains("error") || !results[k].value("success", false))) {
      (void)write_gaze_run_files(runs[k], *keep_failures);
    }
    done.push_back(results[k]);
  }
  return done;
}

}  // namespace

int run_gaze_bench(const GazeBenchOptions& options) {
  const std::vector<GeneratedGazeRun> runs = generate_runs(options);
  const fs::path scratch = make_scratch_folder();
  const std::atomic<bool>& stop = install_stop_signal_handlers();
  std::size_t finished = 0;
  const std::vector<Json> results = run_with_progress(runs, options.jobs, scratch, stop, finished);
  std::error_code ignored;
  fs::remove_all(scratch, ignored);
  const std::vector<Json> done = finished_results(runs, results, options.keep_failures);
  Json summary = summarise_gaze_bench(done, options.seed, options.scenes);
  if (options.json) {
    summary["runs"] = done;
    std::printf("%s\n", json_text(summary).c_str());
  } else {
    print_gaze_bench_table(summary);
  }
  if (stop) {
    std::fprintf(stderr, "gaze-bench: stopped by a signal after %zu of %zu runs\n", finished,
                 runs.size());
    return 128 + stop_signal_number();
  }
  return kExitOk;
}

}  // namespace cambio::app
