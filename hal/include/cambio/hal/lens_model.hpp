#pragma once

#include <cmath>

#include "cambio/hal/camera.hpp"
#include "cambio/hal/image.hpp"

namespace cambio::hal {

/// Where a camera's ideal (pinhole) pixel (u, v) lies in the image its lens makes: OpenCV's and
/// ROS's plumb-bob model on normalised coordinates (x, y) = ((u - cx) / fx, (v - cy) / fy),
/// r^2 = x^2 + y^2: x_d = x (1 + k1 r^2 + k2 r^4 + k3 r^6) + 2 p1 x y + p2 (r^2 + 2 x^2), y_d
/// likewise with p1 and p2 swapped, back to pixels with the same intrinsics (cv::projectPoints's
/// model). Pixel-centre coordinates: (0, 0) is the first pixel's centre, as the intrinsics'.
inline void distort_px(const CameraIntrinsics& k, const PlumbBobDistortion& d, double u, double v,
                       double& u_distorted, double& v_distorted) noexcept {
  const double x = (u - k.principal_x_px) / k.focal_x_px;
  const double y = (v - k.principal_y_px) / k.focal_y_px;
  const double r2 = x * x + y * y;
  const double radial = 1.0 + r2 * (d.k1 + r2 * (d.k2 + r2 * d.k3));
  const double xd = x * radial + 2.0 * d.p1 * x * y + d.p2 * (r2 + 2.0 * x * x);
  const double yd = y * radial + d.p1 * (r2 + 2.0 * y * y) + 2.0 * d.p2 * x * y;
  u_distorted = k.principal_x_px + k.focal_x_px * xd;
  v_distorted = k.principal_y_px + k.focal_y_px * yd;
}

/// The ideal pixel whose image through the lens is (u_distorted, v_distorted): the model inverted
/// by the fixed-point iteration cv::undistortPoints uses. False where it does not reproduce the
/// distorted pixel to 1e-3 px (beyond where the model folds over).
inline bool undistort_px(const CameraIntrinsics& k, const PlumbBobDistortion& d, double u_distorted,
                         double v_distorted, double& u, double& v) noexcept {
  const double xd = (u_distorted - k.principal_x_px) / k.focal_x_px;
  const double yd = (v_distorted - k.principal_y_px) / k.focal_y_px;
  double x = xd;
  double y = yd;
  constexpr int kIterations = 50;
  for (int i = 0; i < kIterations; ++i) {
    const double r2 = x * x + y * y;
    const double radial = 1.0 + r2 * (d.k1 + r2 * (d.k2 + r2 * d.k3));
    if (!(radial > 0.0)) return false;
    const double dx = 2.0 * d.p1 * x * y + d.p2 * (r2 + 2.0 * x * x);
    const double dy = d.p1 * (r2 + 2.0 * y * y) + 2.0 * d.p2 * x * y;
    x = (xd - dx) / radial;
    y = (yd - dy) / radial;
  }
  u = k.principal_x_px + k.focal_x_px * x;
  v = k.principal_y_px + k.focal_y_px * y;
  double u_check = 0.0;
  double v_check = 0.0;
  distort_px(k, d, u, v, u_check, v_check);
  constexpr double kTolerance_px = 1e-3;
  return std::abs(u_check - u_distorted) < kTolerance_px &&
         std::abs(v_check - v_distorted) < kTolerance_px;
}

}  // namespace cambio::hal
