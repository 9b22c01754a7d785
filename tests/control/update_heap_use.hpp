#pragma once

// What a loop's update() takes from the heap, for the tests that hold a loop to the rule that it
// allocates nothing after configure().

#include <cstdint>

#include "cambio/hal/loop.hpp"
#include "cambio/runtime/allocation_counter.hpp"

namespace cambio::control {

/// Heap allocations and frees (runtime::thread_allocation_count, thread_free_count: malloc as
/// well as operator new) summed over the update() calls run through it.
struct UpdateHeapUse {
  std::uint64_t allocations = 0;
  std::uint64_t frees = 0;

  /// loop.update(tick), counting what it allocates and frees.
  hal::Status update(hal::Loop& loop, const hal::LoopTick& tick) {
    const std::uint64_t allocations_before = runtime::thread_allocation_count();
    const std::uint64_t frees_before = runtime::thread_free_count();
    const hal::Status status = loop.update(tick);
    allocations += runtime::thread_allocation_count() - allocations_before;
    frees += runtime::thread_free_count() - frees_before;
    return status;
  }
};

}  // namespace cambio::control
