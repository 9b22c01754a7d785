#include "cambio/runtime/lockstep_executor.hpp"

#include <algorithm>
#include <stdexcept>

#include "cambio/hal/monotonic_clock.hpp"
#include "cambio/hal/torn_reads.hpp"
#include "cambio/runtime/allocation_counter.hpp"

namespace cambio::runtime {

LockstepExecutor::LockstepExecutor(std::vector<ScheduledLoop> loops, std::int64_t start_ns)
    : clock_(start_ns) {
  for (auto& loop : loops) add_loop(loop);
}

void LockstepExecutor::add_loop(ScheduledLoop loop) {
  if (configured_) throw std::logic_error("lockstep executor: add_loop() after configure()");
  validate(loop, "lockstep");
  add_live_loop(loop.loop->name(), loop.schedule.rate_hz);
  loops_.push_back(loop);
}

void LockstepExecutor::configure() {
  stats_.clear();
  stats_.resize(loops_.size());
  next_cycle_.assign(loops_.size(), 0);
  for (std::size_t i = 0; i < loops_.size(); ++i) {
    stats_[i].name = loops_[i].loop->name();
    stats_[i].rate_hz = loops_[i].schedule.rate_hz;
    stats_[i].allocation_exempt = loops_[i].loop->allocates_in_update();
    loops_[i].loop->configure();
  }
  for (auto& scheduled : loops_) scheduled.loop->activate();
  start_ns_ = clock_.now_ns();
  configured_ = true;
}

void LockstepExecutor::run_until_ns(std::int64_t end_ns) {
  if (!configured_) throw std::logic_error("lockstep executor: run before configure()");
  hal::MonotonicClock wall;
  for (;;) {
    // The earliest deadline; ties go to the higher priority, then to the earlier loop.
    std::size_t due = loops_.size();
    std::int64_t due_ns = end_ns;
    for (std::size_t i = 0; i < loops_.size(); ++i) {
      const std::int64_t t = deadline_ns(start_ns_, next_cycle_[i], loops_[i].schedule.rate_hz);
      if (t >= end_ns) continue;
      if (due == loops_.size() || t < due_ns ||
          (t == due_ns && loops_[i].schedule.priority > loops_[due].schedule.priority)) {
        due = i;
        due_ns = t;
      }
    }
    if (due == loops_.size()) break;

    clock_.advance_to_ns(due_ns);
    LoopStatistics& stats = stats_[due];
    const hal::LoopTick tick{next_cycle_[due], due_ns, due_ns, 1.0 / loops_[due].schedule.rate_hz};
    const std::uint64_t allocations_before = thread_allocation_count();
    const std::uint64_t torn_before = hal::thread_torn_read_count();
    const std::int64_t wall_start_ns = wall.now_ns();
    const hal::Status status = loops_[due].loop->update(tick);
    const std::int64_t execution_ns = wall.now_ns() - wall_start_ns;
    stats.execution_time.record_ns(execution_ns);
    live(due).record(0, execution_ns, false);  // Simulated time: never late.
    stats.allocations += thread_allocation_count() - allocations_before;
    stats.torn_reads += hal::thread_torn_read_count() - torn_before;
    stats.wakeup_latency.record_ns(0);
    if (status != hal::Status::kOk && status != hal::Status::kNoNewData) ++stats.failed_updates;
    ++stats.cycles;
    ++next_cycle_[due];
  }
  clock_.advance_to_ns(end_ns);
}

void LockstepExecutor::deactivate() {
  for (std::size_t i = 0; i < loops_.size(); ++i) {
    loops_[i].loop->deactivate();
    if (i < stats_.size()) {
      stats_[i].fault_message = std::string(loops_[i].loop->fault_message());
      stats_[i].faults = loops_[i].loop->fault_count();
    }
  }
  configured_ = false;
}

std::int64_t LockstepExecutor::run(const std::atomic<bool>& stop, std::int64_t duration_ns,
                                   const Progress& progress) {
  configure();
  const std::int64_t start_ns = clock_.now_ns();
  // Simulated time advances in slices so a signal stops the run within one slice and progress
  // is reported as it goes.
  constexpr std::int64_t kSliceNs = 100'000'000;
  std::int64_t done_ns = 0;
  while (done_ns < duration_ns && !stop.load()) {
    done_ns = std::min(duration_ns, done_ns + kSliceNs);
    run_until_ns(start_ns + done_ns);
    if (progress) progress(static_cast<double>(done_ns) * 1e-9);
  }
  deactivate();
  return done_ns;
}

}  // namespace cambio::runtime
