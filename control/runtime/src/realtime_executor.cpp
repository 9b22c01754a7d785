#include "cambio/runtime/realtime_executor.hpp"

#include <pthread.h>
#include <sched.h>
#include <sys/mman.h>

#include <algorithm>
#include <cerrno>
#include <chrono>
#include <cstring>
#include <exception>
#include <iostream>
#include <latch>
#include <mutex>
#include <stdexcept>
#include <thread>

#include "cambio/hal/torn_reads.hpp"
#include "cambio/runtime/allocation_counter.hpp"

namespace cambio::runtime {
namespace {

// Loops start together this long after every loop is configured, so the first deadline is not
// already late.
constexpr std::int64_t kStartDelayNs = 2'000'000;

std::string errno_text(int error) {
  return std::strerror(error);
}

/// The cycle after cycle k, which ended at finished_ns. An overrun is counted; under kSkip the
/// deadlines it passed are dropped, and those inside the run (before `end`) counted as skipped.
std::uint64_t next_cycle(const ScheduledLoop& scheduled, LoopStatistics& stats, std::int64_t start,
                         std::int64_t end, std::uint64_t k, std::int64_t finished_ns) {
  const double rate_hz = scheduled.schedule.rate_hz;
  std::uint64_t next = k + 1;
  if (finished_ns > deadline_ns(start, next, rate_hz)) {
    ++stats.overruns;
    if (scheduled.schedule.overrun == OverrunPolicy::kSkip) {
      while (deadline_ns(start, next, rate_hz) < finished_ns) ++next;
      // Only deadlines inside the run count as skipped; an overrun of the last cycle
      // passes deadlines that were never due.
      std::uint64_t due_end = next;
      while (due_end > k + 1 && deadline_ns(start, due_end - 1, rate_hz) >= end) --due_end;
      stats.skipped_cycles += due_end - k - 1;
    }
  }
  return next;
}

}  // namespace

/// What a run's threads share: the loops' threads with each other (the start, the abort) and
/// with the calling thread (progress, errors).
struct RealtimeExecutor::RunState {
  RunState(const std::atomic<bool>& stop_flag, std::int64_t run_duration_ns, std::size_t loop_count)
      : stop(stop_flag),
        duration_ns(run_duration_ns),
        configured(static_cast<std::ptrdiff_t>(loop_count)),
        errors(loop_count) {}

  const std::atomic<bool>& stop;
  const std::int64_t duration_ns;
  std::mutex warnings_mutex;  // Only used before the cycles start and after they end.
  std::latch configured;
  std::atomic<bool> abort{false};
  std::atomic<std::int64_t> start_ns{0};
  std::atomic<std::size_t> finished{0};
  std::vector<std::exception_ptr> errors;
};

RealtimeExecutor::RealtimeExecutor(std::vector<ScheduledLoop> loops, RealtimeOptions options)
    : options_(options) {
  for (auto& loop : loops) add_loop(loop);
}

void RealtimeExecutor::add_loop(ScheduledLoop loop) {
  validate(loop, "realtime");
  add_live_loop(loop.loop->name(), loop.schedule.rate_hz);
  loops_.push_back(loop);
}

std::int64_t RealtimeExecutor::run(const std::atomic<bool>& stop, std::int64_t duration_ns,
                                   const Progress& progress) {
  warnings_.clear();
  RunState state(stop, duration_ns, loops_.size());

  if (options_.lock_memory && mlockall(MCL_CURRENT | MCL_FUTURE) != 0) {
    warn(state, "mlockall refused (" + errno_text(errno) +
                    "); pages may fault in the loops. Run as root or raise RLIMIT_MEMLOCK.");
  }

  stats_.assign(loops_.size(), LoopStatistics{});
  std::vector<std::thread> threads;
  threads.reserve(loops_.size());
  for (std::size_t index = 0; index < loops_.size(); ++index) {
    threads.emplace_back([this, index, &state] { run_loop(index, state); });
  }

  report_progress_until_finished(state, progress);
  for (auto& thread : threads) thread.join();
  const std::int64_t start = state.start_ns.load();
  std::int64_t done_ns = start == 0 ? 0 : std::max<std::int64_t>(0, clock_.now_ns() - start);
  if (duration_ns > 0) done_ns = std::min(done_ns, duration_ns);

  if (options_.lock_memory) munlockall();
  for (const auto& error : state.errors) {
    if (error) std::rethrow_exception(error);
  }
  return done_ns;
}

void RealtimeExecutor::warn(RunState& state, std::string text) {
  const std::lock_guard lock(state.warnings_mutex);
  if (options_.print_warnings) std::cerr << "warning: " << text << "\n";
  warnings_.push_back(std::move(text));
}

// One loop's thread: its scheduling, configure() and activate(), the common start, the cycles,
// then deactivate().
void RealtimeExecutor::run_loop(std::size_t index, RunState& state) {
  const ScheduledLoop& scheduled = loops_[index];
  LoopStatistics& stats = stats_[index];
  stats.name = scheduled.loop->name();
  stats.rate_hz = scheduled.schedule.rate_hz;
  stats.allocation_exempt = scheduled.loop->allocates_in_update();

  pin_to_cpu(scheduled, stats, state);
  raise_priority(scheduled, stats, state);
  const bool active = configure_and_activate(index, state);
  const std::int64_t start = wait_for_common_start(index, state);
  if (!active || state.abort.load()) {
    if (active) scheduled.loop->deactivate();
    state.finished.fetch_add(1);
    return;
  }

  run_cycles(scheduled, stats, live(index), start, state);
  scheduled.loop->deactivate();
  stats.fault_message = std::string(scheduled.loop->fault_message());
  stats.faults = scheduled.loop->fault_count();
  state.finished.fetch_add(1);
}

void RealtimeExecutor::pin_to_cpu(const ScheduledLoop& scheduled, LoopStatistics& stats,
                                  RunState& state) {
  if (scheduled.schedule.cpu < 0) return;
  cpu_set_t cpus;
  CPU_ZERO(&cpus);
  CPU_SET(scheduled.schedule.cpu, &cpus);
  const int error = pthread_setaffinity_np(pthread_self(), sizeof cpus, &cpus);
  stats.cpu_affinity_granted = error == 0;
  if (error != 0) {
    warn(state, "loop '" + stats.name + "': CPU " + std::to_string(scheduled.schedule.cpu) +
                    " affinity refused (" + errno_text(error) + ")");
  }
}

void RealtimeExecutor::raise_priority(const ScheduledLoop& scheduled, LoopStatistics& stats,
                                      RunState& state) {
  if (scheduled.schedule.priority <= 0) return;
  sched_param param{};
  param.sched_priority = scheduled.schedule.priority;
  const int error = pthread_setschedparam(pthread_self(), SCHED_FIFO, &param);
  stats.realtime_priority_granted = error == 0;
  if (error != 0) {
    warn(state, "loop '" + stats.name + "': SCHED_FIFO priority " +
                    std::to_string(scheduled.schedule.priority) + " refused (" + errno_text(error) +
                    "); running with normal scheduling. Grant CAP_SYS_NICE or an rtprio limit.");
  }
}

// A failure is kept for run() to rethrow, and aborts every loop before its first cycle.
bool RealtimeExecutor::configure_and_activate(std::size_t index, RunState& state) {
  const ScheduledLoop& scheduled = loops_[index];
  try {
    scheduled.loop->configure();
    scheduled.loop->activate();
    return true;
  } catch (...) {
    state.errors[index] = std::current_exception();
    state.abort.store(true);
  }
  return false;
}

std::int64_t RealtimeExecutor::wait_for_common_start(std::size_t index, RunState& state) {
  state.configured.arrive_and_wait();
  // One thread picks the common start; the others wait for it to be published.
  if (index == 0) {
    state.start_ns.store(clock_.now_ns() + kStartDelayNs, std::memory_order_release);
  }
  std::int64_t start = 0;
  while ((start = state.start_ns.load(std::memory_order_acquire)) == 0) std::this_thread::yield();
  return start;
}

// The cycles, on absolute deadlines from `start`, until the duration ends, `stop` is set or
// another loop aborts the run.
void RealtimeExecutor::run_cycles(const ScheduledLoop& scheduled, LoopStatistics& stats,
                                  LiveLoopCounters& live, std::int64_t start, RunState& state) {
  const double rate_hz = scheduled.schedule.rate_hz;
  const std::int64_t end = state.duration_ns > 0 ? start + state.duration_ns : INT64_MAX;
  std::uint64_t k = 0;
  for (;;) {
    const std::int64_t deadline = deadline_ns(start, k, rate_hz);
    if (deadline >= end || state.stop.load(std::memory_order_relaxed) ||
        state.abort.load(std::memory_order_relaxed)) {
      break;
    }
    clock_.sleep_until_ns(deadline);
    const std::int64_t woke = clock_.now_ns();
    const hal::LoopTick tick{k, deadline, woke, 1.0 / rate_hz};
    const std::uint64_t allocations_before = thread_allocation_count();
    const std::uint64_t torn_before = hal::thread_torn_read_count();
    const hal::Status status = scheduled.loop->update(tick);
    const std::int64_t finished_ns = clock_.now_ns();
    stats.allocations += thread_allocation_count() - allocations_before;
    stats.torn_reads += hal::thread_torn_read_count() - torn_before;
    stats.wakeup_latency.record_ns(woke - deadline);
    stats.execution_time.record_ns(finished_ns - woke);
    if (status != hal::Status::kOk && status != hal::Status::kNoNewData) {
      ++stats.failed_updates;
    }
    ++stats.cycles;
    live.record(woke - deadline, finished_ns - woke,
                finished_ns > deadline_ns(start, k + 1, rate_hz));
    k = next_cycle(scheduled, stats, start, end, k, finished_ns);
  }
}

// Reports progress from the calling thread while the loops run.
void RealtimeExecutor::report_progress_until_finished(RunState& state, const Progress& progress) {
  constexpr auto kProgressPeriod = std::chrono::milliseconds(100);
  while (state.finished.load() < loops_.size()) {
    std::this_thread::sleep_for(kProgressPeriod);
    const std::int64_t start = state.start_ns.load(std::memory_order_acquire);
    if (progress && start != 0 && !state.abort.load()) {
      std::int64_t done = std::max<std::int64_t>(0, clock_.now_ns() - start);
      if (state.duration_ns > 0) done = std::min(done, state.duration_ns);
      progress(static_cast<double>(done) * 1e-9);
    }
  }
}

}  // namespace cambio::runtime
