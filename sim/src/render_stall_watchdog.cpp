#include "cambio/sim/render_stall_watchdog.hpp"

#include <unistd.h>

#include <algorithm>
#include <cstdlib>
#include <string_view>
#include <system_error>

#include "cambio/sim/address_space_limit.hpp"

namespace cambio::sim {

namespace {

std::int64_t steady_now_ns() noexcept {
  return std::chrono::duration_cast<std::chrono::nanoseconds>(
             std::chrono::steady_clock::now().time_since_epoch())
      .count();
}

void write_all(std::string_view text) noexcept {
  std::size_t written = 0;
  while (written < text.size()) {
    const ssize_t n = ::write(STDERR_FILENO, text.data() + written, text.size() - written);
    if (n <= 0) return;
    written += static_cast<std::size_t>(n);
  }
}

}  // namespace

std::unique_ptr<RenderStallWatchdog> RenderStallWatchdog::under_address_space_limit(
    std::chrono::nanoseconds stall) {
  const std::string note = address_space_limit_note();
  if (note.empty()) return nullptr;
  const auto seconds = std::chrono::duration_cast<std::chrono::seconds>(stall).count();
  try {
    return std::make_unique<RenderStallWatchdog>(
        stall, "out of memory: the renderer made no progress for " + std::to_string(seconds) +
                   " s" + note +
                   " (Mesa's llvmpipe waits forever for a thread it could not start)");
  } catch (const std::system_error& error) {
    throw OutOfMemory(std::string("cannot start the renderer's watchdog thread: ") + error.what() +
                      note);
  }
}

RenderStallWatchdog::RenderStallWatchdog(std::chrono::nanoseconds stall, std::string message)
    : stall_(stall), message_(std::move(message)), thread_([this] { watch(); }) {}

RenderStallWatchdog::~RenderStallWatchdog() {
  {
    const std::lock_guard<std::mutex> lock(mutex_);
    stopping_ = true;
  }
  wake_.notify_all();
  thread_.join();
}

void RenderStallWatchdog::arm(const char* step) noexcept {
  step_.store(step, std::memory_order_relaxed);
  armed_at_ns_.store(steady_now_ns(), std::memory_order_release);
}

void RenderStallWatchdog::disarm() noexcept {
  armed_at_ns_.store(0, std::memory_order_release);
}

void RenderStallWatchdog::watch() {
  // Polls at a tenth of the stall time (at most a second): a stall is seen within 10% late.
  const auto poll = std::min<std::chrono::nanoseconds>(stall_ / 10, std::chrono::seconds(1));
  std::unique_lock<std::mutex> lock(mutex_);
  while (!wake_.wait_for(lock, poll, [this] { return stopping_; })) {
    const std::int64_t armed_at_ns = armed_at_ns_.load(std::memory_order_acquire);
    if (armed_at_ns == 0 || steady_now_ns() - armed_at_ns < stall_.count()) continue;
    // In pieces: with the address space used up, building one string could itself fail.
    write_all("cambio: ");
    write_all(message_);
    write_all(", while ");
    write_all(step_.load(std::memory_order_relaxed));
    write_all("\n");
    std::_Exit(EXIT_FAILURE);
  }
}

}  // namespace cambio::sim
