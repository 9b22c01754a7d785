#include "cambio/hal/seqlock_channel.hpp"

#include <gtest/gtest.h>

#include <pthread.h>
#include <sched.h>
#include <unistd.h>

#include <array>
#include <atomic>
#include <chrono>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <thread>

namespace cambio::hal {
namespace {

// Every field holds the same counter: a reader that ever sees two different values in one read
// has seen a torn write.
struct Sample {
  std::array<std::uint64_t, 13> fields;
  double as_double;
};

Sample make_sample(std::uint64_t n) {
  Sample s{};
  s.fields.fill(n);
  s.as_double = static_cast<double>(n);
  return s;
}

TEST(SeqlockChannel, ReadsBackTheLastWrite) {
  SeqlockChannel<Sample> channel;
  EXPECT_EQ(channel.version(), 0u);
  channel.write(make_sample(7));
  Sample out{};
  std::uint64_t version = 0;
  EXPECT_TRUE(channel.read(out, &version));
  EXPECT_EQ(version, 1u);
  EXPECT_EQ(out.fields[12], 7u);
  EXPECT_EQ(out.as_double, 7.0);
}

TEST(SeqlockChannel, ConcurrentReaderNeverSeesATornValue) {
  SeqlockChannel<Sample> channel(make_sample(0));
  constexpr std::uint64_t kWrites = 300'000;
  std::atomic<bool> done{false};
  std::atomic<std::uint64_t> torn{0};
  std::atomic<std::uint64_t> reads{0};
  std::atomic<std::uint64_t> went_backwards{0};

  std::thread reader([&] {
    std::uint64_t last = 0;
    Sample out{};
    while (!done.load(std::memory_order_acquire)) {
      channel.read(out);
      for (const auto field : out.fields) {
        if (field != out.fields[0]) ++torn;
      }
      if (out.as_double != static_cast<double>(out.fields[0])) ++torn;
      if (out.fields[0] < last) ++went_backwards;
      last = out.fields[0];
      ++reads;
    }
  });
  // On a loaded machine the writes can all happen before the reader first runs: wait for it, or
  // the test would check nothing.
  while (reads.load() == 0) std::this_thread::yield();
  for (std::uint64_t n = 1; n <= kWrites; ++n) channel.write(make_sample(n));
  done.store(true, std::memory_order_release);
  reader.join();

  EXPECT_EQ(torn.load(), 0u);
  EXPECT_EQ(went_backwards.load(), 0u);
  EXPECT_GT(reads.load(), 0u);
  Sample final_value{};
  channel.read(final_value);
  EXPECT_EQ(final_value.fields[0], kWrites);
}

// Big enough that a write spends microseconds with its sequence odd, so a reader that wakes
// while the writer is preempted finds it mid-write.
struct Page {
  std::array<std::uint64_t, 2048> words;
};

// 0 on success, else the error of pinning to `cpu` and/or switching to SCHED_FIFO `priority`.
int pin_and_prioritise(int cpu, int priority) {
  cpu_set_t cpus;
  CPU_ZERO(&cpus);
  CPU_SET(cpu, &cpus);
  if (const int error = pthread_setaffinity_np(pthread_self(), sizeof cpus, &cpus)) return error;
  sched_param param{};
  param.sched_priority = priority;
  return pthread_setschedparam(pthread_self(), SCHED_FIFO, &param);
}

TEST(SeqlockChannel, AHighPriorityReaderPinnedWithAPreemptedWriterNeverWaitsForIt) {
  // The rig's worst case: reader and writer SCHED_FIFO on one CPU, the reader higher. Whenever
  // the reader wakes it preempts the writer, possibly mid-write; the writer cannot finish until
  // the reader sleeps. An unbounded retry spins forever there; a bounded one gives up, keeps
  // the last good value and counts a torn read.
  if (std::thread::hardware_concurrency() < 2) GTEST_SKIP() << "needs a second CPU to watch";
  SeqlockChannel<Page> channel;
  std::atomic<bool> stop_writer{false};
  std::atomic<int> setup_error{0};
  std::atomic<bool> reader_done{false};
  std::atomic<std::uint64_t> clean_reads{0};
  std::atomic<std::uint64_t> torn_reads{0};
  std::atomic<std::uint64_t> inconsistent{0};

  std::thread writer([&] {
    if (const int error = pin_and_prioritise(0, 10)) {
      setup_error.store(error);
      return;
    }
    Page page{};
    for (std::uint64_t n = 1; !stop_writer.load(std::memory_order_relaxed); ++n) {
      page.words.fill(n);
      channel.write(page);
    }
  });
  std::thread reader([&] {
    if (const int error = pin_and_prioritise(0, 20)) {
      setup_error.store(error);
      reader_done.store(true);
      return;
    }
    Page last_good{};
    const std::uint64_t torn_before = thread_torn_read_count();
    for (int cycle = 0; cycle < 2000; ++cycle) {
      std::this_thread::sleep_for(std::chrono::microseconds(100));  // The loop's period.
      if (channel.read(last_good)) {
        ++clean_reads;
      }
      for (const auto word : last_good.words) {
        if (word != last_good.words[0]) {
          ++inconsistent;
          break;
        }
      }
    }
    torn_reads.store(thread_torn_read_count() - torn_before);
    reader_done.store(true);
  });

  // Watch from another CPU: with an unbounded read the reader never finishes, and the FIFO
  // threads cannot be cancelled, so a hang ends the test process.
  cpu_set_t other;
  CPU_ZERO(&other);
  CPU_SET(1, &other);
  pthread_setaffinity_np(pthread_self(), sizeof other, &other);
  const auto give_up = std::chrono::steady_clock::now() + std::chrono::seconds(20);
  while (!reader_done.load() && std::chrono::steady_clock::now() < give_up) {
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
  }
  if (!reader_done.load()) {
    ADD_FAILURE() << "the reader spun on a preempted writer for 20 s";
    std::fflush(stdout);
    std::_Exit(1);
  }
  stop_writer.store(true);
  reader.join();
  writer.join();
  if (setup_error.load() != 0) {
    GTEST_SKIP() << "SCHED_FIFO or CPU affinity refused (" << std::strerror(setup_error.load())
                 << "): run as root or with CAP_SYS_NICE to test the pinned case";
  }
  EXPECT_EQ(inconsistent.load(), 0u) << "a torn value was returned as good";
  EXPECT_EQ(clean_reads.load() + torn_reads.load(), 2000u);
  EXPECT_GT(torn_reads.load(), 0u) << "the reader never caught the writer mid-write";
  EXPECT_GT(clean_reads.load(), 0u);
}

}  // namespace
}  // namespace cambio::hal
