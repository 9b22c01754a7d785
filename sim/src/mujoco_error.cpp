#include "cambio/sim/mujoco_error.hpp"

#include <array>
#include <atomic>
#include <cstring>
#include <mutex>

#include <mujoco/mujoco.h>

namespace cambio::sim {

namespace {

std::atomic<std::uint64_t> warning_count{0};
// The latest warning, written by the warning handler. A seqlock-like pair keeps the handler
// lock-free: readers retry while a write is in progress.
std::atomic<std::uint64_t> warning_sequence{0};
std::array<char, 256> warning_text{};

void on_error(const char* message) {
  throw MujocoError(std::string("MuJoCo: ") + (message != nullptr ? message : "unknown error"));
}

void on_warning(const char* message) {
  warning_sequence.fetch_add(1, std::memory_order_acq_rel);
  std::strncpy(warning_text.data(), message != nullptr ? message : "", warning_text.size() - 1);
  warning_text.back() = '\0';
  warning_sequence.fetch_add(1, std::memory_order_acq_rel);
  warning_count.fetch_add(1, std::memory_order_relaxed);
}

}  // namespace

void install_mujoco_handlers() {
  static std::once_flag once;
  std::call_once(once, [] {
    mju_user_error = &on_error;
    mju_user_warning = &on_warning;
  });
}

std::uint64_t mujoco_warning_count() noexcept {
  return warning_count.load(std::memory_order_relaxed);
}

std::string last_mujoco_warning() {
  for (;;) {
    const std::uint64_t before = warning_sequence.load(std::memory_order_acquire);
    if (before % 2 != 0) continue;
    std::array<char, 256> copy = warning_text;
    if (warning_sequence.load(std::memory_order_acquire) == before) return std::string(copy.data());
  }
}

}  // namespace cambio::sim
