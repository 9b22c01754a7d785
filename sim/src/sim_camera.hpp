#pragma once

#include <cstdint>
#include <optional>
#include <vector>

#include "cambio/config/rig_config.hpp"
#include "cambio/hal/camera.hpp"
#include "cambio/sim/image_noise.hpp"
#include "cambio/sim/renderer.hpp"
#include "camera_frames.hpp"
#include "sim_lens.hpp"

namespace cambio::sim {

/// A rig camera rendered by MuJoCo from the cameras' shared frame (CameraFrames). grab() renders
/// under a lease on the world's renderer, taken without waiting, then flips, converts (grey8 or
/// rgb8) and adds the configured noise. Both eyes of a stereo pair grabbed in one camera-loop
/// cycle see the same world snapshot, and every image is stamped with that snapshot's time.
/// Optionally foveated (config::SimFoveationConfig). A camera whose rig entry has a lens
/// distortion sees through it (SimLens: whole frames, never foveated).
class SimCamera final : public hal::Camera {
 public:
  /// `foveation` (when enabled) renders a low-resolution field and a full-resolution fovea
  /// (compose_foveated) instead of the whole frame.
  SimCamera(hal::CameraInfo info, int camera_id, Renderer& renderer, CameraFrames& frames,
            double noise_std, std::uint64_t seed, config::SimFoveationConfig foveation = {});

  const hal::CameraInfo& info() const override { return info_; }
  /// No lock, no wait; takes the render's milliseconds of CPU and, inside Mesa and libglvnd, the
  /// heap (grab_allocates()). kNoNewData when no new snapshot was published since this camera's
  /// last image, or when another thread (ground truth) holds the renderer at that moment.
  hal::Status grab(hal::Image& out) override;
  /// True: rendering calls malloc in Mesa's llvmpipe and libglvnd's eglMakeCurrent (70 to 170
  /// times a camera-loop cycle in the shipped experiments), none of it this code's.
  bool grab_allocates() const override { return true; }

  /// Flips the renderer's bottom-up rgb rows into `out`; kGrey8 through hal::luma_bt601.
  static void convert_rows(const std::uint8_t* rgb_bottom_up, int width, int height,
                           hal::PixelFormat format, hal::Image& out) noexcept;

 private:
  hal::CameraInfo info_;
  int camera_id_;
  Renderer& renderer_;
  CameraFrames& frames_;
  ImageNoise noise_;
  bool render_views() noexcept;

  std::optional<SimLens> lens_;  ///< Set when the camera's distortion is not zero.
  config::SimFoveationConfig foveation_;
  /// The whole frame (through a lens: the lens's ideal window), or the periphery when foveated.
  std::vector<std::uint8_t> rgb_;
  std::vector<std::uint8_t> fovea_;             ///< The fovea's window when foveated.
  std::optional<std::uint64_t> rendered_step_;  ///< Step of the snapshot last rendered.
  std::uint64_t sequence_ = 0;
};

}  // namespace cambio::sim
