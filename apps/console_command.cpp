// `cambio console EXPERIMENT.yaml`: the paper's standard-input commands, with the experiment's
// loops running in the background (console_session.hpp carries out each line).
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <condition_variable>
#include <cstdlib>
#include <deque>
#include <iostream>
#include <mutex>
#include <optional>
#include <thread>

#include "argument_parser.hpp"
#include "bounded_line.hpp"
#include "builtin_backends.hpp"
#include "cambio/config/echoed_text.hpp"
#include "command.hpp"
#include "config_errors.hpp"
#include "console_session.hpp"
#include "main_job.hpp"
#include "robot_actions.hpp"
#include "stop_signal.hpp"

namespace cambio::app {
namespace {

constexpr const char* kPrompt = "cambio> ";

/// Lines typed at a terminal, read by a thread of their own so the robot keeps running (and
/// time passes) while the user thinks.
class TerminalLines {
 public:
  TerminalLines() : reader_([this] { read(); }) {}
  ~TerminalLines() { reader_.detach(); }  // It may be blocked in getline: leave it be.
  TerminalLines(const TerminalLines&) = delete;
  TerminalLines& operator=(const TerminalLines&) = delete;

  /// The next line if one was typed; nullopt otherwise. `eof` is set once input has ended.
  std::optional<std::string> try_pop(bool& eof) {
    std::lock_guard lock(mutex_);
    eof = eof_ && lines_.empty();
    if (lines_.empty()) return std::nullopt;
    std::string line = std::move(lines_.front());
    lines_.pop_front();
    return line;
  }
  /// Asks for the next line (prints the prompt) once the last one has been carried out.
  void ready() {
    std::lock_guard lock(mutex_);
    want_ = true;
    wanted_.notify_one();
  }

 private:
  void read() {
    for (;;) {
      {
        std::unique_lock lock(mutex_);
        wanted_.wait(lock, [this] { return want_; });
        want_ = false;
      }
      std::cout << kPrompt << std::flush;
      std::string line;
      const LineRead got = read_bounded_line(std::cin, line);
      std::lock_guard lock(mutex_);
      if (got != LineRead::kLine) {
        too_long_ = got == LineRead::kTooLong;
        eof_ = true;
        return;
      }
      lines_.push_back(std::move(line));
    }
  }

  std::mutex mutex_;
  std::condition_variable wanted_;
  bool want_ = true;
  bool eof_ = false;

 public:
  /// Input ended on a line longer than kMaxInputLineChars.
  bool too_long() {
    std::lock_guard lock(mutex_);
    return too_long_;
  }

 private:
  bool too_long_ = false;
  std::deque<std::string> lines_;
  std::thread reader_;
};

/// Where the console's lines come from: a terminal (the run goes on while the user types) or a
/// pipe or file (read when the previous line is done: a script is deterministic).
class LineSource {
 public:
  explicit LineSource(bool interactive) {
    if (interactive) terminal_.emplace();
  }
  bool interactive() const { return terminal_.has_value(); }
  /// nullopt with `eof` false: nothing typed yet (terminal only).
  std::optional<std::string> next(bool& eof) {
    if (terminal_) {
      std::optional<std::string> line = terminal_->try_pop(eof);
      if (eof && terminal_->too_long()) report_too_long();
      return line;
    }
    std::string line;
    const LineRead got = read_bounded_line(std::cin, line);
    ++line_number_;
    eof = got != LineRead::kLine;
    if (got == LineRead::kTooLong) report_too_long();
    if (eof) return std::nullopt;
    std::cout << kPrompt << line << "\n";  // The transcript shows what was carried out.
    return line;
  }
  void done_with_line() {
    if (terminal_) terminal_->ready();
  }
  /// Input was refused (a line too long): the session ends there, and the command exits 2.
  bool input_refused() const { return input_refused_; }

 private:
  void report_too_long() {
    if (input_refused_) return;
    input_refused_ = true;
    std::cerr << "cambio console: input line " << (terminal_ ? 0 : line_number_)
              << " is longer than " << kMaxInputLineChars
              << " characters: not console commands; stopping the robot and the session\n";
  }

  std::optional<TerminalLines> terminal_;
  int line_number_ = 0;
  bool input_refused_ = false;
};

struct ConsoleRun {
  MainJob& job;
  ConsoleSession& session;
  LineSource& lines;
  const std::atomic<bool>& signal_stop;
  double real_time_factor = 1.0;
};

/// Lockstep: the console decides each step; the simulation runs in 10 ms slices paced to the
/// wall clock at the real-time factor, and stands still while a piped line is read.
MainJobResult run_lockstep(ConsoleRun& run) {
  constexpr std::int64_t kSliceNs = 10'000'000;
  std::int64_t wait_until_ns = 0;
  bool quit = false;
  auto wall_anchor = std::chrono::steady_clock::now();
  std::int64_t sim_anchor_ns = 0;
  return run.job.run_stepped(run.signal_stop, [&](std::int64_t now_ns) -> std::int64_t {
    bool read_a_line = false;
    // The previous command has had its control period: say what the loops refused of it.
    if (now_ns >= wait_until_ns) run.session.report_loop_refusals();
    while (!quit && now_ns >= wait_until_ns) {
      bool eof = false;
      const std::optional<std::string> line = run.lines.next(eof);
      if (!line) {
        quit = eof;
        break;
      }
      read_a_line = true;
      const ConsoleSession::Next next = run.session.execute(*line, now_ns);
      quit = next.quit;
      if (next.wait_s > 0.0) wait_until_ns = now_ns + static_cast<std::int64_t>(next.wait_s * 1e9);
      // A command takes effect at the loops' next cycle; the next line waits for it.
      if (next.sent) wait_until_ns = std::max(wait_until_ns, now_ns + run.job.control_period_ns());
      run.lines.done_with_line();
    }
    // The last command takes effect (and may be refused) before the console ends.
    if (quit && now_ns >= wait_until_ns) {
      run.session.report_loop_refusals();
      return -1;
    }
    if (read_a_line && !run.lines.interactive()) {
      // Reading a piped line took wall time the simulation did not: pace from here.
      wall_anchor = std::chrono::steady_clock::now();
      sim_anchor_ns = now_ns;
    }
    std::int64_t end_ns = now_ns + kSliceNs;
    if (wait_until_ns > now_ns) end_ns = std::min(end_ns, wait_until_ns);
    if (run.real_time_factor > 0.0) {
      const auto due =
          wall_anchor + std::chrono::nanoseconds(static_cast<std::int64_t>(
                            static_cast<double>(end_ns - sim_anchor_ns) / run.real_time_factor));
      // In steps of at most 20 ms, so a stop asked at a tiny factor (one slice of 10 ms at
      // --rtf 1e-6 is almost three hours) ends the wait at once.
      while (!run.signal_stop.load() && std::chrono::steady_clock::now() < due) {
        std::this_thread::sleep_until(
            std::min(due, std::chrono::steady_clock::now() + std::chrono::milliseconds(20)));
      }
    }
    return end_ns;
  });
}

/// Realtime (the rig drives hardware): the executor's threads run the loops; this thread reads
/// lines and sends commands, and `wait S` sleeps S seconds.
MainJobResult run_realtime(ConsoleRun& run) {
  std::atomic<bool> stop_run{false};
  std::atomic<bool> finished{false};
  MainJobResult result;
  std::exception_ptr failure;
  std::thread loops([&] {
    try {
      constexpr double kUntilQuitS = 1e9;
      result = run.job.run(
          stop_run, [](double, double) {}, kUntilQuitS);
    } catch (...) {
      failure = std::current_exception();
    }
    finished = true;
  });
  // A signal stops the loops even while this thread is blocked reading a line.
  std::thread watcher([&] {
    while (!finished.load()) {
      if (run.signal_stop.load()) stop_run = true;
      std::this_thread::sleep_for(std::chrono::milliseconds(20));
    }
  });
  // Waits between lines end early when the run stops (a signal, a device fault): a `wait 3600`
  // must not hold a Ctrl-C for an hour.
  const auto sleep_while_running = [&](std::chrono::nanoseconds duration) {
    const auto until = std::chrono::steady_clock::now() + duration;
    while (!stop_run.load() && !finished.load()) {
      const auto left = until - std::chrono::steady_clock::now();
      if (left <= std::chrono::nanoseconds::zero()) return;
      std::this_thread::sleep_for(
          std::min<std::chrono::nanoseconds>(left, std::chrono::milliseconds(20)));
    }
  };
  const auto start = std::chrono::steady_clock::now();
  while (!stop_run.load() && !finished.load()) {
    bool eof = false;
    const std::optional<std::string> line = run.lines.next(eof);
    if (!line) {
      if (eof) break;
      std::this_thread::sleep_for(std::chrono::milliseconds(20));
      continue;
    }
    const auto now_ns = std::chrono::duration_cast<std::chrono::nanoseconds>(
                            std::chrono::steady_clock::now() - start)
                            .count();
    const ConsoleSession::Next next = run.session.execute(*line, now_ns);
    if (next.quit) break;
    if (next.wait_s > 0.0) {
      sleep_while_running(std::chrono::duration_cast<std::chrono::nanoseconds>(
          std::chrono::duration<double>(next.wait_s)));
    }
    if (next.sent) {
      // Two periods: the command is taken at the loops' next cycle, which may be a period away.
      sleep_while_running(std::chrono::nanoseconds(2 * run.job.control_period_ns()));
      run.session.report_loop_refusals();
    }
    run.lines.done_with_line();
  }
  stop_run = true;
  loops.join();
  watcher.join();
  if (failure) std::rethrow_exception(failure);
  result.stopped_by_signal = run.signal_stop.load();  // Not a quit, which also stops the loops.
  return result;
}

}  // namespace

int run_console_command(std::span<const std::string> args) {
  ArgumentParser parser("console", "EXPERIMENT.yaml [--set KEY=VALUE]... [--rtf FACTOR]");
  parser.positional("EXPERIMENT.yaml", "the experiment whose rig and scene to drive")
      .repeated_option("set", "KEY=VALUE", "override an experiment or (rig.) rig key")
      .option("rtf", "FACTOR",
              "simulated seconds per wall second on the lockstep executor (default 1; 0: as "
              "fast as the loops go)");
  if (!parser.parse(args)) return kExitOk;

  double real_time_factor = 1.0;
  if (parser.has("rtf")) {
    const std::string& text = parser.value("rtf");
    char* end = nullptr;
    real_time_factor = std::strtod(text.c_str(), &end);
    if (text.empty() || *end != '\0' || !std::isfinite(real_time_factor) ||
        real_time_factor < 0.0) {
      std::cerr << "cambio console: --rtf: expected a factor >= 0, found "
                << config::in_quotes(text) << "\n";
      return kExitBadInput;
    }
  }

  config::ExperimentConfig experiment;
  try {
    std::vector<config::ConfigOverride> overrides;
    for (const auto& text : parser.values("set")) overrides.push_back(config::parse_override(text));
    experiment = config::load_experiment(*parser.positional_value("EXPERIMENT.yaml"), overrides);
  } catch (const config::ConfigError& error) {
    report_config_error(error);
    return kExitBadInput;
  }

  // A behaviour decides what the robot does; typed commands would fight it for the gaze.
  if (experiment.behaviour) {
    std::cerr << "cambio console: " << experiment.name << " runs the behaviour '"
              << experiment.behaviour->name
              << "', which commands the gaze; the console takes experiments without one\n";
    return kExitBadInput;
  }

  hal::BackendFactory factory;
  std::unique_ptr<MainJob> job;
  try {
    register_builtin_backends(factory, experiment, nullptr);
    // The console commands the gaze loop itself and evaluates nothing.
    job = std::make_unique<MainJob>(experiment, factory,
                                    MainJobOptions{.send_script = false, .record_trace = false});
  } catch (const hal::BackendUnavailable& error) {
    std::cerr << "cambio console: " << error.what() << "\n";
    return kExitBadInput;
  } catch (const config::ConfigError& error) {
    report_config_error(error);
    return kExitBadInput;
  } catch (const std::runtime_error& error) {
    std::cerr << "cambio console: " << error.what() << "\n";
    return kExitDeviceFault;
  }
  if (job->actions() == nullptr) {
    std::cerr << "cambio console: " << experiment.name
              << ": the console drives the gaze task; this experiment's task is not gaze\n";
    return kExitBadInput;
  }

  std::vector<std::string> objects;
  if (experiment.scene) {
    for (const auto& object : experiment.scene->objects) objects.push_back(object.name);
  }
  ConsoleSession session(*job, *job->actions(), objects, std::cout);

  const bool interactive = isatty(STDIN_FILENO) != 0;
  std::cerr << "cambio console: " << experiment.name << " on rig '" << experiment.rig.name << "', "
            << (job->realtime() ? "realtime executor" : "lockstep executor");
  if (!job->realtime() && real_time_factor > 0.0) {
    std::cerr << " at " << real_time_factor << "x real time";
  } else if (!job->realtime()) {
    std::cerr << " as fast as the loops go";
  }
  std::cerr << (interactive ? "; type help for the commands, quit to stop\n" : "\n");

  const auto& stop = install_stop_signal_handlers();
  LineSource lines(interactive);
  ConsoleRun run{*job, session, lines, stop, real_time_factor};
  MainJobResult result;
  try {
    result = job->realtime() ? run_realtime(run) : run_lockstep(run);
  } catch (const std::exception& error) {
    std::cerr << "cambio console: " << error.what() << "\n";
    return kExitDeviceFault;
  }

  std::cout << runtime::format_statistics_table(result.loops.data(), result.loops.size());
  std::cerr << "cambio console: ran " << result.simulated_s << " s (" << session.lines_refused()
            << " lines refused)\n";
  if (result.stopped_by_signal) return exit_status_for_signal(stop_signal_number());
  if (result.fault_latched_at_end) {
    std::cerr << "cambio console: a device fault stopped the robot (joints held since)\n";
    return kExitDeviceFault;
  }
  return lines.input_refused() ? kExitBadInput : kExitOk;
}

}  // namespace cambio::app
