#pragma once

// A watchdog for a renderer that stops making progress. Under an address-space limit (ulimit -v)
// Mesa's llvmpipe may fail to start one of its rasteriser threads and then wait for it forever
// inside mjr_render: no error, no return, Ctrl-C unheard (the loop that would see it is the one
// stuck). Memory ran out; the program says so and ends, instead of hanging.

#include <atomic>
#include <chrono>
#include <condition_variable>
#include <cstdint>
#include <memory>
#include <mutex>
#include <string>
#include <thread>

namespace cambio::sim {

class RenderStallWatchdog {
 public:
  /// A first render on llvmpipe (shaders compiled) takes well under a second; fifteen is a stall
  /// on any machine.
  static constexpr std::chrono::seconds kDefaultStall{15};

  /// Null without an address-space limit (nothing to watch for); else a started watchdog whose
  /// message names the limit. Throws OutOfMemory if its thread cannot start (memory is short).
  static std::unique_ptr<RenderStallWatchdog> under_address_space_limit(
      std::chrono::nanoseconds stall = kDefaultStall);

  /// Starts the watching thread, idle. When a step stays armed longer than `stall`, writes
  /// `message` and the step's name to standard error and ends the process with exit status 1
  /// (out of memory): a thread stuck inside the GL driver cannot be unwound.
  RenderStallWatchdog(std::chrono::nanoseconds stall, std::string message);
  ~RenderStallWatchdog();
  RenderStallWatchdog(const RenderStallWatchdog&) = delete;
  RenderStallWatchdog& operator=(const RenderStallWatchdog&) = delete;

  /// Marks the start of a step that must finish within the stall time (`step` a string literal,
  /// e.g. "rendering"). Real-time safe: two atomic stores, no allocation, no lock.
  void arm(const char* step) noexcept;
  /// Marks its end. Real-time safe.
  void disarm() noexcept;

  /// arm() for the scope's lifetime, however it is left; a null watchdog watches nothing.
  class Scope {
   public:
    Scope(RenderStallWatchdog* watchdog, const char* step) noexcept : watchdog_(watchdog) {
      if (watchdog_ != nullptr) watchdog_->arm(step);
    }
    ~Scope() {
      if (watchdog_ != nullptr) watchdog_->disarm();
    }
    Scope(const Scope&) = delete;
    Scope& operator=(const Scope&) = delete;

   private:
    RenderStallWatchdog* watchdog_;
  };

 private:
  void watch();

  const std::chrono::nanoseconds stall_;
  const std::string message_;
  std::atomic<std::int64_t> armed_at_ns_{0};  ///< steady_clock; 0 when no step is armed.
  std::atomic<const char*> step_{""};
  std::mutex mutex_;  ///< Guards stopping_ for the watching thread's wait, never the arm side.
  std::condition_variable wake_;
  bool stopping_ = false;
  std::thread thread_;
};

}  // namespace cambio::sim
