#pragma once

#include <cstdint>

namespace cambio::runtime {

/// Heap allocations (operator new, all forms) made so far by the calling thread. The runtime
/// replaces the global operator new to count them, so executors can report allocations per
/// cycle and tests can assert zero. Real-time safe.
std::uint64_t thread_allocation_count() noexcept;

}  // namespace cambio::runtime
