#pragma once

#include <cstdint>

#include <Eigen/Core>
#include <Eigen/Geometry>

#include "cambio/hal/image.hpp"
#include "cambio/perception/motion_estimator.hpp"

namespace cambio::control {

/// Smooth pursuit's belief about where the pursued target is, from the SSM's motion estimate at
/// the dominant eye's fovea (its first consumer).
///
/// The target starts on the dominant eye's optical axis. Each new SSM frame moves its image
/// position by the measured displacement since the estimator's key frame, once the tracker knows
/// where the target was in that key (else by the flow since the previous frame:
/// S_now(p) = S_before(p - flow)); the position, seen from the camera's believed
/// orientation when the frame was exposed, gives the target's direction in the base frame, and
/// successive directions its angular velocity (low-pass filtered). A frame without a motion
/// estimate (first frame, retina moved, untextured fovea) extrapolates with that velocity, and so
/// does one whose estimate would need the target to turn more than 45 deg/s faster than predicted
/// (the fovea's window taken by the surround, not the target).
/// Directions, not points: the target's depth is the caller's (vergence knows it).
/// All methods are allocation-free and real-time safe.
class PursuitTracker {
 public:
  /// `intrinsics`: the dominant camera's; `velocity_filter_s`: time constant of the angular
  /// velocity's low-pass filter (> 0).
  PursuitTracker(const hal::CameraIntrinsics& intrinsics, double velocity_filter_s);

  /// Starts on a target along `direction_W` (need not be unit), seen from a camera whose
  /// orientation was R_WC at `stamp_ns`; the velocity starts at zero.
  void start(const Eigen::Vector3d& direction_W, const Eigen::Matrix3d& R_WC,
             std::int64_t stamp_ns) noexcept;
  void stop() noexcept { active_ = false; }

  /// One SSM frame: the dominant fovea's motion and the camera's believed orientation when that
  /// frame was exposed (at `stamp_ns`). Frames not newer than the last are ignored.
  void update(const perception::MotionResult& motion, const Eigen::Matrix3d& R_WC,
              std::int64_t stamp_ns) noexcept;

  /// The target's unit direction at `t_ns`, extrapolated from the last frame with the filtered
  /// angular velocity.
  Eigen::Vector3d direction_W(std::int64_t t_ns) const noexcept;
  /// Filtered angular velocity of the target's direction (rad/s, base frame).
  const Eigen::Vector3d& angular_velocity_W() const { return angular_velocity_W_; }

  bool active() const { return active_; }
  std::uint64_t measured_frames() const { return measured_frames_; }
  std::uint64_t extrapolated_frames() const { return extrapolated_frames_; }

 private:
  /// `direction` turned by `angular_velocity * dt_s` (Rodrigues).
  static Eigen::Vector3d turned(const Eigen::Vector3d& direction,
                                const Eigen::Vector3d& angular_velocity, double dt_s) noexcept;

  double fx_px_;
  double fy_px_;
  double velocity_filter_s_;
  bool active_ = false;
  std::int64_t stamp_ns_ = 0;
  Eigen::Vector3d direction_W_ = Eigen::Vector3d::UnitX();
  Eigen::Matrix3d R_WC_ = Eigen::Matrix3d::Identity();
  Eigen::Vector3d angular_velocity_W_ = Eigen::Vector3d::Zero();
  /// The target's normalised image position in the motion estimator's key frame, once the
  /// tracker has seen that frame: positions then come from the displacement since the key (no
  /// drift from summing per-frame flows).
  bool have_key_ = false;
  std::uint64_t key_frame_ = 0;
  Eigen::Vector2d key_xy_ = Eigen::Vector2d::Zero();
  std::uint64_t last_frame_ = 0;
  std::uint64_t measured_frames_ = 0;
  std::uint64_t extrapolated_frames_ = 0;
};

}  // namespace cambio::control
