#pragma once

#include "cambio/hal/camera.hpp"
#include "cambio/hal/lens_model.hpp"

namespace cambio::perception {

/// A camera's lens as the SSM reads through it: the plumb-bob model (hal::distort_px) with the
/// camera's intrinsics.
class LensDistortion {
 public:
  LensDistortion() = default;
  LensDistortion(const hal::CameraIntrinsics& intrinsics, const hal::PlumbBobDistortion& distortion)
      : intrinsics_(intrinsics), distortion_(distortion) {}

  /// No distortion (a pinhole): the retina reads pixels as they are.
  bool is_identity() const { return distortion_.is_zero(); }

  /// The distorted image position of the ideal pixel (u, v) (hal::distort_px). Real-time safe.
  void distort_px(double u, double v, double& u_distorted, double& v_distorted) const noexcept {
    hal::distort_px(intrinsics_, distortion_, u, v, u_distorted, v_distorted);
  }

 private:
  hal::CameraIntrinsics intrinsics_;
  hal::PlumbBobDistortion distortion_;
};

}  // namespace cambio::perception
