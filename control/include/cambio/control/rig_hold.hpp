#pragma once

#include <atomic>
#include <cstdint>
#include <stdexcept>

namespace cambio::control {

/// Shared by the joint loops of one rig when its groups run at different rates (one loop per
/// rate): while any loop holds (a latched fault or lost joint, stale feedback), every loop holds,
/// as a single joint loop holds all its joints. Each loop reports only its own reasons, so a
/// loop held for another's fault resumes as soon as that one clears.
class RigHold {
 public:
  static constexpr int kMaxLoops = 64;

  /// A slot for one more loop. Not real-time safe (call while building the loops).
  int add_loop() {
    if (loops_ == kMaxLoops) throw std::length_error("rig hold: more than 64 joint loops");
    return loops_++;
  }
  /// Real-time safe, wait-free, any thread.
  void set(int slot, bool holding) noexcept {
    const std::uint64_t bit = std::uint64_t{1} << slot;
    if (holding) {
      holding_.fetch_or(bit, std::memory_order_acq_rel);
    } else {
      holding_.fetch_and(~bit, std::memory_order_acq_rel);
    }
  }
  /// Whether a loop other than `slot` holds. Real-time safe, wait-free, any thread.
  bool others_holding(int slot) const noexcept {
    return (holding_.load(std::memory_order_acquire) & ~(std::uint64_t{1} << slot)) != 0;
  }

 private:
  std::atomic<std::uint64_t> holding_{0};
  int loops_ = 0;
};

}  // namespace cambio::control
