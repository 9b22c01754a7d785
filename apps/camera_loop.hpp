#pragma once

#include <memory>
#include <string>
#include <vector>

#include "cambio/hal/camera.hpp"
#include "cambio/hal/loop.hpp"
#include "cambio/hal/triple_buffer.hpp"

namespace cambio::app {

/// Grabs every camera at the camera loop's rate and publishes each frame on its own
/// latest-value channel. Frames are allocated at configure; grabbing copies into them.
class CameraLoop final : public hal::Loop {
 public:
  /// Allocates one channel per camera, sized from its info (readers may attach at once).
  explicit CameraLoop(std::vector<hal::Camera*> cameras);

  const std::string& name() const override { return name_; }
  /// Grabs one frame from each camera (discarded) so the backend's first-frame setup happens
  /// here, not in update().
  void configure() override;
  hal::Status update(const hal::LoopTick& tick) noexcept override;

  /// The channel of camera `index` (in constructor order).
  hal::TripleBuffer<hal::Image>& frames(std::size_t index) { return *channels_[index]; }
  std::uint64_t frames_grabbed() const { return frames_grabbed_; }

 private:
  std::string name_ = "camera";
  std::vector<hal::Camera*> cameras_;
  std::vector<std::unique_ptr<hal::TripleBuffer<hal::Image>>> channels_;
  std::uint64_t frames_grabbed_ = 0;
};

}  // namespace cambio::app
