#pragma once

#include <array>
#include <atomic>
#include <cstdint>
#include <cstring>
#include <type_traits>

#include "cambio/hal/torn_reads.hpp"

namespace cambio::hal {

/// Latest-value channel for small trivially copyable values (joint targets, a disparity): one
/// writer, any number of readers, neither ever blocks or allocates.
///
/// The value is stored as relaxed atomic words so that a reader racing a writer reads stale or
/// mixed words, never undefined behaviour; the sequence counter tells it to retry. A write is
/// never torn from the reader's view: try_read() only returns values whose sequence was even and
/// unchanged across the copy.
template <class T>
class SeqlockChannel {
  static_assert(std::is_trivially_copyable_v<T>, "SeqlockChannel holds trivially copyable values");

 public:
  SeqlockChannel() {
    write(T{});
    sequence_.store(0, std::memory_order_relaxed);
  }
  explicit SeqlockChannel(const T& initial) {
    write(initial);
    sequence_.store(0, std::memory_order_relaxed);
  }

  /// Single writer. Wait-free; real-time safe.
  void write(const T& value) noexcept {
    std::array<std::uint64_t, kWords> staged{};
    std::memcpy(staged.data(), static_cast<const void*>(&value), sizeof(T));
    const std::uint64_t seq = sequence_.load(std::memory_order_relaxed);
    sequence_.store(seq + 1, std::memory_order_relaxed);
    std::atomic_thread_fence(std::memory_order_release);
    for (std::size_t i = 0; i < kWords; ++i) words_[i].store(staged[i], std::memory_order_relaxed);
    sequence_.store(seq + 2, std::memory_order_release);
  }

  /// One attempt; false if a write was in progress. Wait-free; real-time safe.
  bool try_read(T& out, std::uint64_t* version = nullptr) const noexcept {
    const std::uint64_t before = sequence_.load(std::memory_order_acquire);
    if (before & 1u) return false;
    std::array<std::uint64_t, kWords> staged{};
    for (std::size_t i = 0; i < kWords; ++i) staged[i] = words_[i].load(std::memory_order_relaxed);
    std::atomic_thread_fence(std::memory_order_acquire);
    if (sequence_.load(std::memory_order_relaxed) != before) return false;
    std::memcpy(static_cast<void*>(&out), staged.data(), sizeof(T));
    if (version != nullptr) *version = before / 2;
    return true;
  }

  /// Tries up to kReadAttempts times for a consistent copy. Never waits on the writer: under
  /// SCHED_FIFO with both threads pinned to one CPU a preempted writer cannot finish while the
  /// reader runs, so an unbounded retry would spin forever. On failure `out` is left untouched
  /// (the caller keeps its last good value) and the torn read is counted on this thread
  /// (thread_torn_read_count()). Returns true if `out` now holds the newest value. Wait-free;
  /// real-time safe.
  bool read(T& out, std::uint64_t* version = nullptr) const noexcept {
    for (int attempt = 0; attempt < kReadAttempts; ++attempt) {
      if (try_read(out, version)) return true;
    }
    count_torn_read();
    return false;
  }

  /// A write copies a few cache lines; a reader on another CPU that sees it in progress this
  /// many times in a row is racing a writer that is not running.
  static constexpr int kReadAttempts = 64;

  /// Number of writes so far. Real-time safe.
  std::uint64_t version() const noexcept { return sequence_.load(std::memory_order_acquire) / 2; }

 private:
  static constexpr std::size_t kWords = (sizeof(T) + 7) / 8;
  std::atomic<std::uint64_t> sequence_{0};
  std::array<std::atomic<std::uint64_t>, kWords> words_{};
};

}  // namespace cambio::hal
