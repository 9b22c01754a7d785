#pragma once

#include "cambio/hal/camera.hpp"
#include "cambio/hal/triple_buffer.hpp"

namespace cambio::app {

/// A hal::Camera that serves the newest frame the camera loop published, so a consumer running
/// at another rate (the perception loop) gets frames without grabbing from the device a second
/// time. The only reader of its channel.
class LatestFrameCamera final : public hal::Camera {
 public:
  LatestFrameCamera(const hal::CameraInfo& info, hal::TripleBuffer<hal::Image>& frames)
      : info_(info), frames_(frames) {}

  const hal::CameraInfo& info() const override { return info_; }

  /// kNoNewData until the camera loop publishes a frame not served yet. Real-time safe: a copy
  /// into `out`, which has the camera's size.
  hal::Status grab(hal::Image& out) override {
    if (out.width_px != info_.intrinsics.width_px || out.height_px != info_.intrinsics.height_px ||
        out.format != info_.format) {
      return hal::Status::kRejected;
    }
    if (!frames_.acquire()) return hal::Status::kNoNewData;
    out = frames_.front();  // Same size: reuses out's buffer.
    return hal::Status::kOk;
  }

  /// The newest frame published (sequence 0 if none), taking it if nobody has. Reader side
  /// only: call it when no loop is grabbing through this camera.
  const hal::Image& newest_frame() {
    frames_.acquire();
    return frames_.front();
  }

 private:
  hal::CameraInfo info_;
  hal::TripleBuffer<hal::Image>& frames_;
};

}  // namespace cambio::app
