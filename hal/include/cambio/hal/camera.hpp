#pragma once

#include <string>

#include "cambio/hal/image.hpp"
#include "cambio/hal/status.hpp"

namespace cambio::hal {

struct CameraInfo {
  std::string name;        ///< e.g. "left_eye"; unique in the rig.
  std::string frame_name;  ///< The rig frame the camera is mounted in (its pose name).
  CameraIntrinsics intrinsics;
  PixelFormat format = PixelFormat::kGrey8;
  double rate_hz = 30.0;  ///< Rate of the loop that grabs from it.
};

/// One camera. Implemented once per backend (sim: rendered; later V4L2).
/// Lifecycle: the backend constructs it configured; `grab()` is called from one loop thread.
class Camera {
 public:
  virtual ~Camera() = default;

  /// Static description. Thread-safe; real-time safe.
  virtual const CameraInfo& info() const = 0;

  /// Copies the newest frame into `out`, which must already have info()'s size and format
  /// (kRejected otherwise). Returns kNoNewData when no frame arrived since the last grab.
  /// Real-time safe: no allocation, no blocking beyond the copy (the sim renders here, which
  /// takes milliseconds of CPU; run it in its own loop at camera rate).
  virtual Status grab(Image& out) = 0;
};

}  // namespace cambio::hal
