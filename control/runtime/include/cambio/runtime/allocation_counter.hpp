#pragma once

#include <cstdint>

namespace cambio::runtime {

/// Heap allocations made so far by the calling thread: every call of malloc, calloc, realloc
/// (unless it only frees), memalign, aligned_alloc, posix_memalign, valloc and pvalloc, hence
/// every operator new (which calls malloc), from C++ and C code alike. The runtime replaces
/// glibc's allocation functions (under a sanitizer, installs its allocator hooks) to count them,
/// so executors can report allocations per cycle and tests can assert zero. Real-time safe.
std::uint64_t thread_allocation_count() noexcept;

/// Blocks returned to the heap so far by the calling thread (free of a non-null pointer, the old
/// block of a realloc, hence every operator delete). Real-time safe.
std::uint64_t thread_free_count() noexcept;

}  // namespace cambio::runtime
