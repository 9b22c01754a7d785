// The renderer's watchdog under an address-space limit (sim/src/render_stall_watchdog.cpp): a
// step armed past the stall time ends the process with exit 1 and says why; steps that finish in
// time, however many, never do.
#include <sys/resource.h>

#include <chrono>
#include <thread>

#include <gtest/gtest.h>

#include "cambio/sim/render_stall_watchdog.hpp"

namespace cambio::sim {
namespace {

using std::chrono::milliseconds;

TEST(RenderStallWatchdog, AStepArmedPastTheStallEndsTheProcessSayingWhy) {
  GTEST_FLAG_SET(death_test_style, "threadsafe");
  EXPECT_EXIT(
      {
        RenderStallWatchdog watchdog(milliseconds(200), "out of memory: no progress");
        watchdog.arm("rendering");
        std::this_thread::sleep_for(std::chrono::seconds(5));
        std::exit(0);  // Reached only if the watchdog did not fire.
      },
      testing::ExitedWithCode(1), "cambio: out of memory: no progress, while rendering");
}

TEST(RenderStallWatchdog, StepsThatFinishInTimeNeverEndTheProcess) {
  RenderStallWatchdog watchdog(milliseconds(200), "must not fire");
  const auto end = std::chrono::steady_clock::now() + milliseconds(1000);
  int steps = 0;
  while (std::chrono::steady_clock::now() < end) {
    const RenderStallWatchdog::Scope step(&watchdog, "rendering");
    std::this_thread::sleep_for(milliseconds(50));
    ++steps;
  }
  // Idle (disarmed) for longer than the stall: not a stall either.
  std::this_thread::sleep_for(milliseconds(500));
  EXPECT_GE(steps, 5);
}

TEST(RenderStallWatchdog, IsStartedOnlyUnderAnAddressSpaceLimit) {
  rlimit limit{};
  ASSERT_EQ(getrlimit(RLIMIT_AS, &limit), 0);
  const bool limited = limit.rlim_cur != RLIM_INFINITY;
  EXPECT_EQ(RenderStallWatchdog::under_address_space_limit() != nullptr, limited);
}

}  // namespace
}  // namespace cambio::sim
