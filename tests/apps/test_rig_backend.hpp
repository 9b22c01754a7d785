#pragma once

// A backend that lives in tests/ alone: ideal drives (a joint is where it was last commanded,
// once enabled) behind the HAL's JointGroup, with counters a test reads. It shows what adding a
// backend takes: this folder and one registration call, nothing of the run assembly.

#include <atomic>
#include <cstdint>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include "cambio/hal/backend_factory.hpp"

namespace cambio::testing {

/// What the backend saw, for the test to assert on (read after the run).
struct TestRigRecord {
  int configures = 0;
  int activates = 0;
  int deactivates = 0;
  std::atomic<std::uint64_t> writes{0};  ///< write() calls over every group.
  std::atomic<std::uint64_t> reads{0};
  /// Each joint's newest position (rad), by name.
  std::map<std::string, double> positions_rad;
};

/// Registers backend "test_rig": joint groups only (a camera or touch sensor is refused). Joints
/// start `start_offset_rad` away from their initial position. `record` outlives every run.
void register_test_rig_backend(hal::BackendFactory& factory, TestRigRecord& record,
                               double start_offset_rad);

}  // namespace cambio::testing
