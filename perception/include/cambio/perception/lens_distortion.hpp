#pragma once

#include "cambio/hal/camera.hpp"

namespace cambio::perception {

/// Where a camera's ideal (pinhole) pixel lies in the image its lens makes: OpenCV's and ROS's
/// plumb-bob model on normalised coordinates (x, y) = ((u - cx) / fx, (v - cy) / fy), r^2 = x^2 +
/// y^2: x_d = x (1 + k1 r^2 + k2 r^4 + k3 r^6) + 2 p1 x y + p2 (r^2 + 2 x^2), y_d likewise with
/// p1 and p2 swapped, back to pixels with the same intrinsics (cv::projectPoints's model).
/// Pixel-centre coordinates: (0, 0) is the first pixel's centre, as the intrinsics'.
class LensDistortion {
 public:
  LensDistortion() = default;
  LensDistortion(const hal::CameraIntrinsics& intrinsics, const hal::PlumbBobDistortion& distortion)
      : intrinsics_(intrinsics), distortion_(distortion) {}

  /// No distortion (a pinhole, as the sim renders): the retina reads pixels as they are.
  bool is_identity() const { return distortion_.is_zero(); }

  /// The distorted image position of the ideal pixel (u, v). Real-time safe.
  void distort_px(double u, double v, double& u_distorted, double& v_distorted) const noexcept {
    const hal::CameraIntrinsics& k = intrinsics_;
    const hal::PlumbBobDistortion& d = distortion_;
    const double x = (u - k.principal_x_px) / k.focal_x_px;
    const double y = (v - k.principal_y_px) / k.focal_y_px;
    const double r2 = x * x + y * y;
    const double radial = 1.0 + r2 * (d.k1 + r2 * (d.k2 + r2 * d.k3));
    const double xd = x * radial + 2.0 * d.p1 * x * y + d.p2 * (r2 + 2.0 * x * x);
    const double yd = y * radial + d.p1 * (r2 + 2.0 * y * y) + 2.0 * d.p2 * x * y;
    u_distorted = k.principal_x_px + k.focal_x_px * xd;
    v_distorted = k.principal_y_px + k.focal_y_px * yd;
  }

 private:
  hal::CameraIntrinsics intrinsics_;
  hal::PlumbBobDistortion distortion_;
};

}  // namespace cambio::perception
