#pragma once

#include <cstdint>
#include <optional>
#include <vector>

#include "cambio/hal/camera.hpp"
#include "cambio/sim/image_noise.hpp"
#include "cambio/sim/renderer.hpp"
#include "camera_frames.hpp"

namespace cambio::sim {

/// A rig camera rendered by MuJoCo from the cameras' shared frame (CameraFrames). grab() renders
/// under a lease on the world's renderer, taken without waiting, then flips, converts (grey8 or
/// rgb8) and adds the configured noise. Both eyes of a stereo pair grabbed in one camera-loop
/// cycle see the same world snapshot, and every image is stamped with that snapshot's time.
class SimCamera final : public hal::Camera {
 public:
  SimCamera(hal::CameraInfo info, int camera_id, Renderer& renderer, CameraFrames& frames,
            double noise_std, std::uint64_t seed);

  const hal::CameraInfo& info() const override { return info_; }
  /// Real-time safe (no allocation, no lock, no wait); takes the render's milliseconds of CPU.
  /// kNoNewData when no new snapshot was published since this camera's last image, or when
  /// another thread (ground truth) holds the renderer at that moment.
  hal::Status grab(hal::Image& out) override;

  /// Flips the renderer's bottom-up rgb rows into `out`; kGrey8 through hal::luma_bt601.
  static void convert_rows(const std::uint8_t* rgb_bottom_up, int width, int height,
                           hal::PixelFormat format, hal::Image& out) noexcept;

 private:
  hal::CameraInfo info_;
  int camera_id_;
  Renderer& renderer_;
  CameraFrames& frames_;
  ImageNoise noise_;
  std::vector<std::uint8_t> rgb_;
  std::optional<std::uint64_t> rendered_step_;  ///< Step of the snapshot last rendered.
  std::uint64_t sequence_ = 0;
};

}  // namespace cambio::sim
