#pragma once

#include <array>
#include <string>

#include <Eigen/Geometry>

#include "cambio/hal/image.hpp"
#include "cambio/hal/status.hpp"

namespace cambio::hal {

/// Lens distortion, OpenCV's / ROS's "plumb_bob" model: radial k1, k2, k3 and tangential
/// p1, p2 on normalised image coordinates. All zero for an ideal pinhole (the sim).
struct PlumbBobDistortion {
  double k1 = 0.0;
  double k2 = 0.0;
  double p1 = 0.0;
  double p2 = 0.0;
  double k3 = 0.0;

  bool is_zero() const { return k1 == 0.0 && k2 == 0.0 && p1 == 0.0 && p2 == 0.0 && k3 == 0.0; }
  /// In OpenCV's order (k1, k2, p1, p2, k3), for cv::undistortPoints and ViSP.
  std::array<double, 5> opencv_order() const { return {k1, k2, p1, p2, k3}; }
};

struct CameraInfo {
  std::string name;     ///< e.g. "left_eye"; unique in the rig.
  std::string backend;  ///< The name its backend registered with.
  /// The link the camera is mounted on: "base" or a joint's name (each joint moves a link named
  /// after it), as in HardwareInfo.
  std::string parent_frame;
  /// Pose of the optical frame (OpenCV: z forward, x right, y down) in the parent link frame:
  /// with the kinematics' X_WP, X_WC = X_WP * X_PC.
  Eigen::Isometry3d X_PC = Eigen::Isometry3d::Identity();
  CameraIntrinsics intrinsics;
  PlumbBobDistortion distortion;
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
  /// Real-time safe: no allocation (unless grab_allocates()), no blocking beyond the copy (the sim
  /// renders here, which takes milliseconds of CPU; run it in its own loop at camera rate).
  virtual Status grab(Image& out) = 0;

  /// True for a camera whose grab() uses the heap: the sim's, whose renderer (Mesa's llvmpipe,
  /// behind libglvnd) calls malloc in every frame. A loop grabbing one says so
  /// (Loop::allocates_in_update()); it is no camera for a real-time loop.
  virtual bool grab_allocates() const { return false; }
};

}  // namespace cambio::hal
