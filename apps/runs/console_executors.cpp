#include "console_executors.hpp"

#include <algorithm>
#include <chrono>
#include <exception>
#include <thread>

namespace cambio::app {

namespace {

/// Sleeps until `due` on the wall clock, in steps of at most 20 ms, so a stop asked at a tiny
/// factor (one slice of 10 ms at --rtf 1e-6 is almost three hours) ends the wait at once.
void sleep_until_due(std::chrono::steady_clock::time_point due, const std::atomic<bool>& stop) {
  while (!stop.load() && std::chrono::steady_clock::now() < due) {
    std::this_thread::sleep_until(
        std::min(due, std::chrono::steady_clock::now() + std::chrono::milliseconds(20)));
  }
}

/// Sleeps `duration`, ending early when the run stops (a signal, a device fault): a `wait 3600`
/// must not hold a Ctrl-C for an hour.
void sleep_while_running(std::chrono::nanoseconds duration, const std::atomic<bool>& stop_run,
                         const std::atomic<bool>& finished) {
  const auto until = std::chrono::steady_clock::now() + duration;
  while (!stop_run.load() && !finished.load()) {
    const auto left = until - std::chrono::steady_clock::now();
    if (left <= std::chrono::nanoseconds::zero()) return;
    std::this_thread::sleep_for(
        std::min<std::chrono::nanoseconds>(left, std::chrono::milliseconds(20)));
  }
}

/// Reads and carries out lines while the loops run, until a quit, the end of input, or the run
/// stopping.
void carry_out_lines(ConsoleRun& run, const std::atomic<bool>& stop_run,
                     const std::atomic<bool>& finished) {
  const auto start = std::chrono::steady_clock::now();
  while (!stop_run.load() && !finished.load()) {
    bool eof = false;
    const std::optional<std::string> line = run.lines.next(eof);
    if (!line) {
      if (eof) return;
      std::this_thread::sleep_for(std::chrono::milliseconds(20));
      continue;
    }
    const auto now_ns = std::chrono::duration_cast<std::chrono::nanoseconds>(
                            std::chrono::steady_clock::now() - start)
                            .count();
    const ConsoleSession::Next next = run.session.execute(*line, now_ns);
    if (next.quit) return;
    if (next.wait_s > 0.0) {
      sleep_while_running(std::chrono::duration_cast<std::chrono::nanoseconds>(
                              std::chrono::duration<double>(next.wait_s)),
                          stop_run, finished);
    }
    if (next.sent) {
      // Two periods: the command is taken at the loops' next cycle, which may be a period away.
      sleep_while_running(std::chrono::nanoseconds(2 * run.job.control_period_ns()), stop_run,
                          finished);
      run.session.report_loop_refusals();
    }
    run.lines.done_with_line();
  }
}

}  // namespace

MainJobResult run_console_lockstep(ConsoleRun& run) {
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
      sleep_until_due(
          wall_anchor + std::chrono::nanoseconds(static_cast<std::int64_t>(
                            static_cast<double>(end_ns - sim_anchor_ns) / run.real_time_factor)),
          run.signal_stop);
    }
    return end_ns;
  });
}

MainJobResult run_console_realtime(ConsoleRun& run) {
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
  carry_out_lines(run, stop_run, finished);
  stop_run = true;
  loops.join();
  watcher.join();
  if (failure) std::rethrow_exception(failure);
  result.stopped_by_signal = run.signal_stop.load();  // Not a quit, which also stops the loops.
  return result;
}

}  // namespace cambio::app
