// The loop side never allocates after configure(): this runs a small but complete runtime (a
// joint loop, a control loop, a camera loop and a perception loop exchanging data through the
// latest-value channels) and counts every heap allocation its loops make. First, the counter
// itself: C's allocation functions as well as operator new, each once, per thread.
#include <gtest/gtest.h>

#include <atomic>
#include <cmath>
#include <cstdlib>
#include <numeric>
#include <thread>

#include "cambio/hal/image.hpp"
#include "cambio/hal/joint_group.hpp"
#include "cambio/hal/monotonic_clock.hpp"
#include "cambio/hal/seqlock_channel.hpp"
#include "cambio/hal/torn_reads.hpp"
#include "cambio/hal/triple_buffer.hpp"
#include "cambio/runtime/allocation_counter.hpp"
#include "cambio/runtime/lockstep_executor.hpp"
#include "cambio/runtime/realtime_executor.hpp"

namespace cambio::runtime {
namespace {

constexpr int kJoints = 5;
struct JointTargets {
  std::array<hal::JointCommand, kJoints> commands{};
};
struct JointStates {
  std::array<hal::JointState, kJoints> states{};
  std::int64_t stamp_ns = 0;
};
struct ImageMean {
  double mean = 0.0;
  std::uint64_t sequence = 0;
};

struct Channels {
  hal::SeqlockChannel<JointTargets> targets;
  hal::SeqlockChannel<JointStates> states;
  hal::TripleBuffer<hal::Image> frames{hal::Image(160, 120, hal::PixelFormat::kGrey8)};
  hal::SeqlockChannel<ImageMean> perception;
};

class NamedLoop : public hal::Loop {
 public:
  explicit NamedLoop(std::string name) : name_(std::move(name)) {}
  const std::string& name() const override { return name_; }

 private:
  std::string name_;
};

// Tracks targets with a first-order servo, as a joint loop over a real backend would.
class JointLoop final : public NamedLoop {
 public:
  explicit JointLoop(Channels& c) : NamedLoop("joint"), channels_(c) {}
  hal::Status update(const hal::LoopTick& tick) noexcept override {
    JointTargets targets;
    channels_.targets.read(targets);
    for (int j = 0; j < kJoints; ++j) {
      auto& state = state_.states[static_cast<std::size_t>(j)];
      const double error = targets.commands[static_cast<std::size_t>(j)].value - state.position_rad;
      state.velocity_rad_s = 20.0 * error;
      state.position_rad += state.velocity_rad_s * tick.period_s;
    }
    state_.stamp_ns = tick.deadline_ns;
    channels_.states.write(state_);
    return hal::Status::kOk;
  }

 private:
  Channels& channels_;
  JointStates state_;
};

class ControlLoop final : public NamedLoop {
 public:
  explicit ControlLoop(Channels& c) : NamedLoop("control"), channels_(c) {}
  hal::Status update(const hal::LoopTick& tick) noexcept override {
    JointStates states;
    channels_.states.read(states);
    ImageMean seen;
    channels_.perception.read(seen);
    JointTargets targets;
    for (int j = 0; j < kJoints; ++j) {
      targets.commands[static_cast<std::size_t>(j)].value =
          0.1 * std::sin(1e-9 * static_cast<double>(tick.deadline_ns) + j) + 1e-4 * seen.mean;
    }
    channels_.targets.write(targets);
    return hal::Status::kOk;
  }

 private:
  Channels& channels_;
};

class CameraLoop final : public NamedLoop {
 public:
  explicit CameraLoop(Channels& c) : NamedLoop("camera"), channels_(c) {}
  hal::Status update(const hal::LoopTick& tick) noexcept override {
    hal::Image& frame = channels_.frames.back();
    frame.sequence = tick.cycle + 1;
    frame.stamp_ns = tick.deadline_ns;
    std::fill(frame.pixels.begin(), frame.pixels.end(),
              static_cast<std::uint8_t>(tick.cycle & 0xff));
    channels_.frames.publish();
    return hal::Status::kOk;
  }

 private:
  Channels& channels_;
};

class PerceptionLoop final : public NamedLoop {
 public:
  explicit PerceptionLoop(Channels& c) : NamedLoop("perception"), channels_(c) {}
  void configure() override { working_.resize(160, 120, hal::PixelFormat::kGrey8); }
  hal::Status update(const hal::LoopTick&) noexcept override {
    if (!channels_.frames.acquire()) return hal::Status::kNoNewData;
    working_ = channels_.frames.front();  // Same size: reuses working_'s buffer.
    const double sum = std::accumulate(working_.pixels.begin(), working_.pixels.end(), 0.0);
    channels_.perception.write(
        {sum / static_cast<double>(working_.pixels.size()), working_.sequence});
    return hal::Status::kOk;
  }

 private:
  Channels& channels_;
  hal::Image working_;
};

// A loop that allocates, to show the counter sees what it claims to see; it may declare it.
class AllocatingLoop final : public NamedLoop {
 public:
  explicit AllocatingLoop(bool declares = false) : NamedLoop("allocating"), declares_(declares) {}
  bool allocates_in_update() const override { return declares_; }
  hal::Status update(const hal::LoopTick&) noexcept override {
    try {
      scratch_.push_back(std::vector<int>(16));
    } catch (...) {
      return hal::Status::kFault;
    }
    return hal::Status::kOk;
  }

 private:
  bool declares_;
  std::vector<std::vector<int>> scratch_;
};

// Keeps the compiler from removing an allocation whose block is never read (it may drop a
// malloc/free or new/delete pair otherwise).
template <class T>
T* escape(T* p) {
  asm volatile("" : : "g"(p) : "memory");
  return p;
}

TEST(AllocationCounter, CountsCAllocationFunctionsOnTheCallingThread) {
  const std::uint64_t allocations = thread_allocation_count();
  const std::uint64_t frees = thread_free_count();
  void* a = escape(std::malloc(24));
  void* b = escape(std::calloc(4, 16));
  a = escape(std::realloc(a, 1 << 16));  // A new block, the old one freed.
  void* c = escape(std::aligned_alloc(64, 128));
  void* d = nullptr;
  const int aligned = posix_memalign(&d, 64, 128);
  escape(d);
  const std::uint64_t allocated = thread_allocation_count() - allocations;
  const std::uint64_t freed_by_realloc = thread_free_count() - frees;
  for (void* p : {a, b, c, d}) std::free(p);
  std::free(nullptr);  // Nothing returned to the heap.
  const std::uint64_t freed = thread_free_count() - frees;

  EXPECT_EQ(aligned, 0);
  EXPECT_EQ(allocated, 5u) << "malloc, calloc, realloc, aligned_alloc, posix_memalign";
  EXPECT_EQ(freed_by_realloc, 1u);
  EXPECT_EQ(freed, 5u);
}

TEST(AllocationCounter, AnOperatorNewIsOneAllocation) {
  const std::uint64_t allocations = thread_allocation_count();
  const std::uint64_t frees = thread_free_count();
  auto* block = escape(new std::array<char, 100>);
  const std::uint64_t allocated = thread_allocation_count() - allocations;
  delete block;
  const std::uint64_t freed = thread_free_count() - frees;
  EXPECT_EQ(allocated, 1u);
  EXPECT_EQ(freed, 1u);
}

TEST(AllocationCounter, AnotherThreadsAllocationsAreItsOwn) {
  constexpr int kBlocks = 100;
  std::atomic<int> stage{0};  // 1: the worker may allocate; 2: it has.
  std::uint64_t worker_allocations = 0;
  std::thread worker([&] {
    while (stage.load() != 1) std::this_thread::yield();
    const std::uint64_t before = thread_allocation_count();
    for (int i = 0; i < kBlocks; ++i) std::free(escape(std::malloc(32)));
    worker_allocations = thread_allocation_count() - before;
    stage.store(2);
  });
  const std::uint64_t before = thread_allocation_count();
  stage.store(1);
  while (stage.load() != 2) std::this_thread::yield();
  const std::uint64_t here = thread_allocation_count() - before;
  worker.join();
  EXPECT_EQ(worker_allocations, static_cast<std::uint64_t>(kBlocks));
  EXPECT_EQ(here, 0u) << "the worker's allocations counted on this thread";
}

LoopSchedule rate(double hz) {
  LoopSchedule loop;
  loop.rate_hz = hz;
  return loop;
}

TEST(Allocation, LockstepRuntimeWithChannelsAllocatesNothingOver10000Cycles) {
  Channels channels;
  JointLoop joint(channels);
  ControlLoop control(channels);
  CameraLoop camera(channels);
  PerceptionLoop perception(channels);
  LockstepExecutor executor(
      {{&joint, rate(1000)}, {&control, rate(200)}, {&perception, rate(60)}, {&camera, rate(30)}});
  executor.configure();

  const std::uint64_t before = thread_allocation_count();
  executor.run_until_ns(10'000'000'000);  // 10,000 joint cycles.
  const std::uint64_t after = thread_allocation_count();

  EXPECT_EQ(after - before, 0u) << "heap allocations while the loops ran";
  for (const auto& stats : executor.statistics()) {
    EXPECT_EQ(stats.allocations, 0u) << stats.name;
    EXPECT_EQ(stats.failed_updates, 0u) << stats.name;
  }
  EXPECT_EQ(executor.statistics()[0].cycles, 10'000u);
  // The data really flowed: the perception loop saw the camera's frames.
  ImageMean seen;
  channels.perception.read(seen);
  EXPECT_EQ(seen.sequence, 300u);
}

TEST(Allocation, RealtimeRuntimeWithChannelsAllocatesNothing) {
  Channels channels;
  JointLoop joint(channels);
  ControlLoop control(channels);
  CameraLoop camera(channels);
  PerceptionLoop perception(channels);
  RealtimeExecutor executor(
      {{&joint, rate(1000)}, {&control, rate(200)}, {&perception, rate(60)}, {&camera, rate(30)}},
      {false, /*print_warnings=*/false});
  const std::atomic<bool> never{false};
  executor.run(never, 500'000'000);
  for (const auto& stats : executor.statistics()) {
    EXPECT_GT(stats.cycles, 0u) << stats.name;
    EXPECT_EQ(stats.allocations, 0u) << stats.name;
  }
}

TEST(Allocation, TheCounterSeesAnAllocatingLoop) {
  AllocatingLoop allocating;
  LockstepExecutor executor({{&allocating, rate(100)}});
  executor.configure();
  executor.run_until_ns(100'000'000);
  EXPECT_GE(executor.statistics()[0].allocations, 10u);
  EXPECT_FALSE(executor.statistics()[0].allocation_exempt);
  EXPECT_FALSE(passes_allocation_gate(executor.statistics()[0]));
}

TEST(Allocation, ALoopThatDeclaresItAllocatesIsCountedButExemptFromTheGate) {
  AllocatingLoop declared(/*declares=*/true);
  LockstepExecutor executor({{&declared, rate(100)}});
  executor.configure();
  executor.run_until_ns(100'000'000);
  const LoopStatistics& stats = executor.statistics()[0];
  EXPECT_GE(stats.allocations, 10u);
  EXPECT_TRUE(stats.allocation_exempt);
  EXPECT_TRUE(passes_allocation_gate(stats));
  EXPECT_NE(format_statistics_table(&stats, 1).find("declared to allocate"), std::string::npos);
}

// Gives up on a latest-value read every other cycle (as SeqlockChannel::read does when its
// writer is stuck mid-write).
class TornReadingLoop final : public NamedLoop {
 public:
  TornReadingLoop() : NamedLoop("torn") {}
  hal::Status update(const hal::LoopTick& tick) noexcept override {
    if (tick.cycle % 2 == 0) hal::count_torn_read();
    return hal::Status::kOk;
  }
};

TEST(Allocation, ExecutorsCountEachLoopsTornReads) {
  TornReadingLoop lockstep_loop;
  LockstepExecutor lockstep({{&lockstep_loop, rate(100)}});
  lockstep.configure();
  lockstep.run_until_ns(100'000'000);
  EXPECT_EQ(lockstep.statistics()[0].torn_reads, 5u);

  TornReadingLoop realtime_loop;
  RealtimeExecutor realtime({{&realtime_loop, rate(100)}}, {false, /*print_warnings=*/false});
  const std::atomic<bool> never{false};
  realtime.run(never, 100'000'000);
  const LoopStatistics& stats = realtime.statistics()[0];
  EXPECT_EQ(stats.torn_reads, (stats.cycles + 1) / 2);
}

}  // namespace
}  // namespace cambio::runtime
