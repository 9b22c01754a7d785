#include "cambio/sim/mujoco_error.hpp"

#include <array>
#include <atomic>
#include <cctype>
#include <cstring>
#include <mutex>
#include <string_view>

#include <mujoco/mujoco.h>

#include "cambio/sim/address_space_limit.hpp"

namespace cambio::sim {

namespace {

std::atomic<std::uint64_t> warning_count{0};
// The latest warning, written by the warning handler. A seqlock-like pair keeps the handler
// lock-free: readers retry while a write is in progress.
std::atomic<std::uint64_t> warning_sequence{0};
std::array<char, 256> warning_text{};

/// MuJoCo words every failed allocation "could not allocate ..." (mjData, the model, textures,
/// framebuffers): memory ran out, whatever object it was for.
bool is_allocation_failure(std::string_view message) {
  constexpr std::string_view kPrefix = "could not allocate";
  if (message.size() < kPrefix.size()) return false;
  for (std::size_t i = 0; i < kPrefix.size(); ++i) {
    if (std::tolower(static_cast<unsigned char>(message[i])) != kPrefix[i]) return false;
  }
  return true;
}

void on_error(const char* message) {
  const std::string text = message != nullptr ? message : "unknown error";
  if (is_allocation_failure(text))
    throw OutOfMemory("MuJoCo: " + text + address_space_limit_note());
  throw MujocoError("MuJoCo: " + text);
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
