#include "gaze_bench_runs.hpp"

#include <fcntl.h>
#include <poll.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cerrno>
#include <cstdio>
#include <fstream>
#include <optional>
#include <stdexcept>
#include <string>

#include "builtin_backends.hpp"
#include "cambio/config/experiment_config.hpp"
#include "gaze_bench_score.hpp"
#include "main_job.hpp"

namespace cambio::app {

namespace {

namespace fs = std::filesystem;

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
              {"target_shape", run.target_shape},
              {"target_texture", run.target_texture},
              {"second_depth_m", run.second_depth_m},
              {"pursuit_speed_deg_s", run.pursuit_speed_deg_s},
              {"distractors", run.distractors},
              {"verged_at_s", to_json(score.verged_at_s)},
              {"first_verged_s", to_json(score.first_verged_s)},
              {"final_error_deg", to_json(score.final_error_deg)},
              {"worst_error_deg", to_json(score.worst_error_deg)},
              {"off_target_s", score.off_target_s},
              {"longest_off_target_s", score.longest_off_target_s},
              {"occluded_s", score.occluded_s},
              {"pursuit_rms_deg", to_json(score.pursuit_rms_deg)},
              {"calibration", calibration}};
}

Json error_json(const GeneratedGazeRun& run, const std::string& error) {
  return Json{{"name", run.name}, {"task", std::string(task_name(run.task))}, {"error", error}};
}

/// In the child: runs and scores one generated run, returns its JSON (or an error object).
Json run_one(const GeneratedGazeRun& run, const fs::path& scratch) {
  try {
    const fs::path experiment_file = write_gaze_run_files(run, scratch);
    const config::ExperimentConfig experiment = config::load_experiment(experiment_file.string());
    hal::BackendFactory factory;
    register_builtin_backends(factory, experiment);
    MainJob job(experiment, factory);
    const std::atomic<bool> never{false};
    (void)job.run(never, [](double, double) {});
    if (job.trace() == nullptr) throw std::runtime_error("the run recorded no trace");
    return score_json(run, score_gaze_run(run, *job.trace()));
  } catch (const std::exception& error) {
    return error_json(run, error.what());
  }
}

struct Child {
  pid_t pid = -1;
  int fd = -1;
  std::size_t run = 0;
  std::string output;
};

/// Forks a child that runs `run` and writes its JSON into a pipe, and then exits.
Child start_child(const GeneratedGazeRun& run, std::size_t index, const fs::path& scratch) {
  int pipe_fds[2];
  if (::pipe2(pipe_fds, O_CLOEXEC) != 0) throw std::runtime_error("pipe failed");
  std::fflush(nullptr);
  const pid_t pid = ::fork();
  if (pid < 0) throw std::runtime_error("fork failed");
  if (pid == 0) {
    ::close(pipe_fds[0]);
    const std::string text = run_one(run, scratch).dump();
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
  return {pid, pipe_fds[0], index, {}};
}

/// Reaps a child whose pipe has closed; its JSON, or an error object when it sent none.
Json finish_child(Child& child, const GeneratedGazeRun& run) {
  ::close(child.fd);
  int status = 0;
  while (::waitpid(child.pid, &status, 0) < 0 && errno == EINTR) {
  }
  Json result = Json::parse(child.output, nullptr, false);
  if (result.is_discarded() || !result.is_object()) {
    result = error_json(
        run, "the run's process ended with status " + std::to_string(status) + " and no result");
  }
  return result;
}

/// Waits up to 200 ms for output, reads what there is, and hands on the runs whose children
/// have ended (removing them from `children`).
void collect_output(std::vector<Child>& children, const std::vector<GeneratedGazeRun>& runs,
                    const std::function<void(std::size_t, Json)>& done) {
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
      Json result = finish_child(child, runs[child.run]);
      done(child.run, std::move(result));
      fds.erase(fds.begin() + static_cast<std::ptrdiff_t>(k));
      children.erase(children.begin() + static_cast<std::ptrdiff_t>(k));
      continue;
    }
    ++k;
  }
}

}  // namespace

fs::path write_gaze_run_files(const GeneratedGazeRun& run, const fs::path& directory) {
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

void run_in_child_processes(const std::vector<GeneratedGazeRun>& runs, int jobs,
                            const fs::path& scratch, const std::atomic<bool>& stop,
                            const std::function<void(std::size_t, Json)>& done) {
  std::vector<Child> children;
  std::size_t next = 0;
  while ((next < runs.size() && !stop) || !children.empty()) {
    while (next < runs.size() && !stop && static_cast<int>(children.size()) < jobs) {
      children.push_back(start_child(runs[next], next, scratch));
      ++next;
    }
    collect_output(children, runs, done);
  }
}

}  // namespace cambio::app
