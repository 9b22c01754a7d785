#pragma once

#include <cstdint>

namespace cambio::hal {

namespace detail {
inline thread_local std::uint64_t torn_reads_on_this_thread = 0;
}  // namespace detail

/// Latest-value reads on the calling thread that gave up because a writer was mid-write every
/// time they looked (SeqlockChannel::read's bounded attempts). Executors take the difference
/// around each update() and report it per loop, as they do for allocations. Real-time safe.
inline std::uint64_t thread_torn_read_count() noexcept {
  return detail::torn_reads_on_this_thread;
}

inline void count_torn_read() noexcept {
  ++detail::torn_reads_on_this_thread;
}

}  // namespace cambio::hal
