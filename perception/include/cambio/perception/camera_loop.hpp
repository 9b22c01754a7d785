#pragma once

#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "cambio/hal/camera.hpp"
#include "cambio/hal/loop.hpp"
#include "cambio/hal/stereo_frame.hpp"
#include "cambio/hal/triple_buffer.hpp"

namespace cambio::perception {

/// Which two cameras (indices into the loop's camera list) form the stereo pair.
struct StereoPairIndices {
  std::size_t left = 0;
  std::size_t right = 1;
};

/// Grabs every camera at the camera loop's rate. The stereo pair's two images are published
/// together as one hal::StereoFrame (a consumer never pairs a new left image with an old right
/// one); every other camera on a channel of its own. Frames are allocated at construction;
/// grabbing copies into them. Real-time safe after configure() when its cameras are: a camera
/// whose grab() allocates (hal::Camera::grab_allocates, the sim's) makes the loop declare it.
class CameraLoop final : public hal::Loop {
 public:
  /// Allocates the channels, sized from the cameras' info (readers may attach at once). Throws
  /// std::invalid_argument for a bad pair.
  CameraLoop(std::vector<hal::Camera*> cameras, std::optional<StereoPairIndices> stereo);

  const std::string& name() const override { return name_; }
  /// Grabs one frame from each camera (discarded) so the backend's first-frame setup (contexts,
  /// shader compilation, buffer mapping) happens here, not in update().
  void configure() override;
  /// True when one of its cameras' grab() allocates.
  bool allocates_in_update() const override;
  /// kOk, or the most severe grab status. A pair is published once both eyes delivered a new
  /// image since the last pair.
  hal::Status update(const hal::LoopTick& tick) noexcept override;

  /// The channel of a camera outside the stereo pair (constructor order). One reader.
  hal::TripleBuffer<hal::Image>& frames(std::size_t camera_index);
  /// The stereo pairs. One reader (the perception loop). Throws if the loop has no pair.
  hal::TripleBuffer<hal::StereoFrame>& stereo_frames();
  /// The same pairs on a channel of their own, for one more reader (the ROS 2 bridge's images):
  /// made on the first call, which must come before the executor runs the loop; each published
  /// pair is then copied into it too (same sizes: no allocation). Throws if the loop has no pair.
  hal::TripleBuffer<hal::StereoFrame>& observed_stereo_frames();
  bool has_stereo() const { return stereo_channel_ != nullptr; }

  std::uint64_t frames_grabbed() const { return frames_grabbed_; }
  std::uint64_t pairs_published() const { return pairs_published_; }
  /// Cycles that ended with only one eye's new image waiting for its partner.
  std::uint64_t incomplete_pairs() const { return incomplete_pairs_; }

 private:
  std::string name_ = "camera";
  std::vector<hal::Camera*> cameras_;
  std::optional<StereoPairIndices> stereo_;
  std::vector<std::unique_ptr<hal::TripleBuffer<hal::Image>>> channels_;  // Null for the pair.
  std::unique_ptr<hal::TripleBuffer<hal::StereoFrame>> stereo_channel_;
  std::unique_ptr<hal::TripleBuffer<hal::StereoFrame>> observed_stereo_channel_;
  std::uint64_t frames_grabbed_ = 0;
  std::uint64_t pairs_published_ = 0;
  std::uint64_t incomplete_pairs_ = 0;
  bool left_new_ = false;  // A new image waits in the pair's back slot.
  bool right_new_ = false;
};

}  // namespace cambio::perception
