#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "cambio/hal/camera.hpp"
#include "cambio/hal/image.hpp"
#include "cambio/sim/renderer.hpp"

namespace cambio::sim {

/// A sim camera's lens (its rig entry's plumb-bob distortion): MuJoCo renders a pinhole, so the
/// camera renders the ideal view over a window widened until it holds the ideal position of every
/// pixel of the distorted image, and each distorted pixel is then read from there (bilinear, the
/// positions from hal::undistort_px once at construction). A real camera's lens, as calibrate
/// stereo finds it, is then what the sim's eyes see.
class SimLens {
 public:
  /// The widened window of the camera's image plane to render (same pixel scale, centred on the
  /// image), or nullopt with `why` set where the model folds over inside the image.
  static std::optional<ImageWindow> ideal_window(const hal::CameraIntrinsics& intrinsics,
                                                 const hal::PlumbBobDistortion& distortion,
                                                 std::string* why = nullptr);

  /// Throws std::invalid_argument naming the camera where the model folds over inside the image.
  explicit SimLens(const hal::CameraInfo& info);

  const ImageWindow& window() const { return window_; }
  /// Bytes of the ideal render (rgb8, the renderer's bottom-up rows).
  std::size_t ideal_bytes() const;

  /// Writes the distorted image into `out` (grey8 or rgb8, the camera's size) from the ideal
  /// render of window(). Real-time safe.
  void apply(const std::uint8_t* ideal_rgb_bottom_up, hal::Image& out) const noexcept;

 private:
  /// Where distorted pixel i reads: the byte offset of the ideal pixel to its upper left in the
  /// render, and its position between that pixel and the next ones.
  struct Tap {
    std::int32_t offset = 0;
    float fraction_x = 0.0f;
    float fraction_y = 0.0f;
  };
  ImageWindow window_;
  std::vector<Tap> taps_;
};

}  // namespace cambio::sim
