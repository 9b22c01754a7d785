#pragma once

#include <cstdint>
#include <optional>

#include "cambio/hal/triple_buffer.hpp"
#include "cambio/sim/world_snapshot.hpp"

namespace cambio::sim {

/// The world snapshot the cameras of one renderer show, shared by them so that both eyes of a
/// camera-loop cycle see the same instant: a camera moves the frame on to the newest published
/// snapshot only once it has rendered the current one, so its partner, grabbing next, renders
/// the same frame. Used only by the thread holding the renderer's lease (which also makes it the
/// snapshots' one reader). Real-time safe.
class CameraFrames {
 public:
  explicit CameraFrames(hal::TripleBuffer<WorldSnapshot>& snapshots) : snapshots_(snapshots) {}

  /// The frame for a camera that last rendered the snapshot of step `rendered_step` (none if it
  /// never rendered); nullptr while nothing has been published.
  const WorldSnapshot* frame_for(std::optional<std::uint64_t> rendered_step) noexcept {
    const bool seen_current = has_frame_ && rendered_step == snapshots_.front().step;
    if (!has_frame_ || seen_current) has_frame_ = snapshots_.acquire() || has_frame_;
    return has_frame_ ? &snapshots_.front() : nullptr;
  }

 private:
  hal::TripleBuffer<WorldSnapshot>& snapshots_;
  bool has_frame_ = false;
};

}  // namespace cambio::sim
