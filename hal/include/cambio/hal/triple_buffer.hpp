#pragma once

#include <array>
#include <atomic>
#include <cstdint>
#include <utility>

namespace cambio::hal {

/// Latest-value channel for large values (images, feature maps): one writer thread and one
/// reader thread. Three slots are built up front; afterwards neither side allocates, locks or
/// waits. The writer fills its back slot and swaps it into the middle; the reader swaps the
/// middle into its front slot when something new is there. The reader always sees a whole
/// value, the newest one published before its last acquire().
template <class T>
class TripleBuffer {
 public:
  /// Each slot starts as a copy of `prototype` (give it the final size, e.g. an allocated image).
  explicit TripleBuffer(const T& prototype = T{}) : slots_{prototype, prototype, prototype} {}

  TripleBuffer(const TripleBuffer&) = delete;
  TripleBuffer& operator=(const TripleBuffer&) = delete;

  /// Writer side: the slot to fill. Stays the writer's until publish().
  T& back() noexcept { return slots_[back_]; }

  /// Writer side: makes back() the newest value. Wait-free.
  void publish() noexcept {
    const std::uint8_t previous =
        middle_.exchange(static_cast<std::uint8_t>(back_ | kFreshBit), std::memory_order_acq_rel);
    back_ = previous & kIndexMask;
    published_.fetch_add(1, std::memory_order_relaxed);
  }

  /// Reader side: takes the newest published value if there is one. Returns true if front()
  /// changed. Wait-free.
  bool acquire() noexcept {
    if ((middle_.load(std::memory_order_relaxed) & kFreshBit) == 0) return false;
    const std::uint8_t previous = middle_.exchange(front_, std::memory_order_acq_rel);
    front_ = previous & kIndexMask;
    return true;
  }

  /// Reader side: the value taken by the last acquire().
  const T& front() const noexcept { return slots_[front_]; }

  /// Total publishes so far (any thread).
  std::uint64_t published_count() const noexcept {
    return published_.load(std::memory_order_relaxed);
  }

 private:
  static constexpr std::uint8_t kFreshBit = 0x4;
  static constexpr std::uint8_t kIndexMask = 0x3;
  std::array<T, 3> slots_;
  std::uint8_t back_ = 0;                // Owned by the writer.
  std::atomic<std::uint8_t> middle_{1};  // Shared: index | kFreshBit.
  std::uint8_t front_ = 2;               // Owned by the reader.
  std::atomic<std::uint64_t> published_{0};
};

}  // namespace cambio::hal
