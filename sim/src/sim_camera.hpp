#pragma once

#include <cstdint>
#include <vector>

#include "cambio/hal/camera.hpp"
#include "cambio/hal/triple_buffer.hpp"
#include "cambio/sim/image_noise.hpp"
#include "cambio/sim/renderer.hpp"

namespace cambio::sim {

/// A rig camera rendered by MuJoCo from the newest world snapshot. grab() renders (holding the
/// world's renderer), then flips, converts (grey8 or rgb8) and adds the configured noise.
/// Both eyes of a stereo pair grabbed in one camera-loop cycle see the same world state: the
/// renderer moves to a newer snapshot only once this camera has seen the current one.
class SimCamera final : public hal::Camera {
 public:
  SimCamera(hal::CameraInfo info, int camera_id, Renderer& renderer,
            hal::TripleBuffer<WorldSnapshot>& snapshots, double noise_std, std::uint64_t seed);

  const hal::CameraInfo& info() const override { return info_; }
  /// Real-time safe (no allocation); takes the render's milliseconds of CPU.
  hal::Status grab(hal::Image& out) override;

  /// Flips the renderer's bottom-up rgb rows into `out`; kGrey8 through hal::luma_bt601.
  static void convert_rows(const std::uint8_t* rgb_bottom_up, int width, int height,
                           hal::PixelFormat format, hal::Image& out) noexcept;

 private:
  hal::CameraInfo info_;
  int camera_id_;
  Renderer& renderer_;
  hal::TripleBuffer<WorldSnapshot>& snapshots_;
  ImageNoise noise_;
  std::vector<std::uint8_t> rgb_;
  std::uint64_t rendered_step_ = 0;
  bool rendered_once_ = false;
  std::uint64_t sequence_ = 0;
};

}  // namespace cambio::sim
