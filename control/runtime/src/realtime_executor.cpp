#include "cambio/runtime/realtime_executor.hpp"

#include <pthread.h>
#include <sched.h>
#include <sys/mman.h>

#include <cerrno>
#include <cstring>
#include <exception>
#include <iostream>
#include <latch>
#include <mutex>
#include <stdexcept>
#include <thread>

#include "cambio/runtime/allocation_counter.hpp"

namespace cambio::runtime {
namespace {

// Loops start together this long after every loop is configured, so the first deadline is not
// already late.
constexpr std::int64_t kStartDelayNs = 2'000'000;

std::string errno_text(int error) {
  return std::strerror(error);
}

}  // namespace

RealtimeExecutor::RealtimeExecutor(hal::Clock& clock, std::vector<ScheduledLoop> loops,
                                   RealtimeOptions options)
    : clock_(clock), loops_(std::move(loops)), options_(options) {
  for (const auto& scheduled : loops_) {
    if (scheduled.loop == nullptr) throw std::invalid_argument("realtime executor: null loop");
    if (!(scheduled.schedule.rate_hz > 0.0)) {
      throw std::invalid_argument("realtime executor: loop '" + scheduled.loop->name() +
                                  "' has rate_hz <= 0");
    }
    if (scheduled.schedule.priority < 0 || scheduled.schedule.priority > 99) {
      throw std::invalid_argument("realtime executor: loop '" + scheduled.loop->name() +
                                  "' has priority outside 0..99");
    }
  }
}

std::vector<std::string> RealtimeExecutor::run(const std::atomic<bool>& stop,
                                               std::int64_t duration_ns, bool print_warnings) {
  std::vector<std::string> warnings;
  std::mutex warnings_mutex;  // Only used before the cycles start and after they end.
  auto warn = [&](std::string text) {
    const std::lock_guard lock(warnings_mutex);
    if (print_warnings) std::cerr << "warning: " << text << "\n";
    warnings.push_back(std::move(text));
  };

  if (options_.lock_memory && mlockall(MCL_CURRENT | MCL_FUTURE) != 0) {
    warn("mlockall refused (" + errno_text(errno) +
         "); pages may fault in the loops. Run as root or raise RLIMIT_MEMLOCK.");
  }

  stats_.assign(loops_.size(), LoopStatistics{});
  std::latch configured(static_cast<std::ptrdiff_t>(loops_.size()));
  std::atomic<bool> abort{false};
  std::atomic<std::int64_t> start_ns{0};
  std::vector<std::exception_ptr> errors(loops_.size());
  std::vector<std::thread> threads;
  threads.reserve(loops_.size());

  for (std::size_t index = 0; index < loops_.size(); ++index) {
    threads.emplace_back([&, index] {
      const ScheduledLoop& scheduled = loops_[index];
      LoopStatistics& stats = stats_[index];
      stats.name = scheduled.loop->name();
      stats.rate_hz = scheduled.schedule.rate_hz;

      if (scheduled.schedule.cpu >= 0) {
        cpu_set_t cpus;
        CPU_ZERO(&cpus);
        CPU_SET(scheduled.schedule.cpu, &cpus);
        const int error = pthread_setaffinity_np(pthread_self(), sizeof cpus, &cpus);
        stats.cpu_affinity_granted = error == 0;
        if (error != 0) {
          warn("loop '" + stats.name + "': CPU " + std::to_string(scheduled.schedule.cpu) +
               " affinity refused (" + errno_text(error) + ")");
        }
      }
      if (scheduled.schedule.priority > 0) {
        sched_param param{};
        param.sched_priority = scheduled.schedule.priority;
        const int error = pthread_setschedparam(pthread_self(), SCHED_FIFO, &param);
        stats.realtime_priority_granted = error == 0;
        if (error != 0) {
          warn("loop '" + stats.name + "': SCHED_FIFO priority " +
               std::to_string(scheduled.schedule.priority) + " refused (" + errno_text(error) +
               "); running with normal scheduling. Grant CAP_SYS_NICE or an rtprio limit.");
        }
      }

      bool active = false;
      try {
        scheduled.loop->configure();
        scheduled.loop->activate();
        active = true;
      } catch (...) {
        errors[index] = std::current_exception();
        abort.store(true);
      }
      configured.arrive_and_wait();
      // One thread picks the common start; the others wait for it to be published.
      if (index == 0) {
        start_ns.store(clock_.now_ns() + kStartDelayNs, std::memory_order_release);
      }
      std::int64_t start = 0;
      while ((start = start_ns.load(std::memory_order_acquire)) == 0) std::this_thread::yield();
      if (!active || abort.load()) {
        if (active) scheduled.loop->deactivate();
        return;
      }

      const double rate_hz = scheduled.schedule.rate_hz;
      const std::int64_t end = duration_ns > 0 ? start + duration_ns : INT64_MAX;
      std::uint64_t k = 0;
      for (;;) {
        const std::int64_t deadline = deadline_ns(start, k, rate_hz);
        if (deadline >= end || stop.load(std::memory_order_relaxed) ||
            abort.load(std::memory_order_relaxed)) {
          break;
        }
        clock_.sleep_until_ns(deadline);
        const std::int64_t woke = clock_.now_ns();
        const hal::LoopTick tick{k, deadline, woke, 1.0 / rate_hz};
        const std::uint64_t allocations_before = thread_allocation_count();
        const hal::Status status = scheduled.loop->update(tick);
        const std::int64_t finished = clock_.now_ns();
        stats.allocations += thread_allocation_count() - allocations_before;
        stats.wakeup_latency.record_ns(woke - deadline);
        stats.execution_time.record_ns(finished - woke);
        if (status != hal::Status::kOk && status != hal::Status::kNoNewData) {
          ++stats.failed_updates;
        }
        ++stats.cycles;

        std::uint64_t next = k + 1;
        if (finished > deadline_ns(start, next, rate_hz)) {
          ++stats.overruns;
          if (scheduled.schedule.overrun == config::OverrunPolicy::kSkip) {
            while (deadline_ns(start, next, rate_hz) < finished) ++next;
            // Only deadlines inside the run count as skipped; an overrun of the last cycle
            // passes deadlines that were never due.
            std::uint64_t due_end = next;
            while (due_end > k + 1 && deadline_ns(start, due_end - 1, rate_hz) >= end) --due_end;
            stats.skipped_cycles += due_end - k - 1;
          }
        }
        k = next;
      }
      scheduled.loop->deactivate();
    });
  }
  for (auto& thread : threads) thread.join();

  if (options_.lock_memory) munlockall();
  for (const auto& error : errors) {
    if (error) std::rethrow_exception(error);
  }
  return warnings;
}

}  // namespace cambio::runtime
