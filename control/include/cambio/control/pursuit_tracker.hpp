#pragma once

#include <cstdint>

#include <Eigen/Core>
#include <Eigen/Geometry>

#include "cambio/hal/image.hpp"
#include "cambio/perception/fixated_region.hpp"
#include "cambio/perception/motion_estimator.hpp"
#include "cambio/perception/retina.hpp"

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
///
/// The fovea alone cannot see a target move along its own stripes or edge (the aperture
/// problem: horizontal stripes on a target moving sideways show no motion at all), and the eye
/// would lag until the target's outline reached the fovea, then follow the outline. Where the
/// motion is measured in one direction only (MotionResult::one_directional), the tracker takes the
/// motion along that direction and, across it, the centre of the fixated object's region (the
/// zero-disparity filter: FixatedRegion) when there is one, else its own prediction. The region's
/// centre is held relative to the target as the tracker first saw both (the fixated point need not
/// be the region's centre). Where the fovea has structure both ways, the region is not used: the
/// motion is the finer measurement. Directions, not points: the target's depth is the caller's
/// (vergence knows it). All methods are allocation-free and real-time safe.
class PursuitTracker {
 public:
  /// `intrinsics`: the dominant camera's; `velocity_filter_s`: time constant of the angular
  /// velocity's low-pass filter (> 0).
  PursuitTracker(const hal::CameraIntrinsics& intrinsics, double velocity_filter_s);

  /// Starts on a target along `direction_W` (need not be unit), seen from a camera whose
  /// orientation was R_WC at `stamp_ns`; the velocity starts at zero. `region`, when valid, is
  /// the fixated object's region in a frame where the target was on the camera's axis (the
  /// fixation it is pursued from), measured from `fixation` (image px); without one, the first
  /// region update() gets stands for the target where the tracker then believes it.
  void start(const Eigen::Vector3d& direction_W, const Eigen::Matrix3d& R_WC, std::int64_t stamp_ns,
             const perception::FixatedRegion& region = {},
             perception::PixelPoint fixation = {}) noexcept;
  void stop() noexcept { active_ = false; }

  /// One SSM frame: the dominant fovea's motion and the camera's believed orientation when that
  /// frame was exposed (at `stamp_ns`), and the fixated object's region with the dominant eye's
  /// fixation point (image px) it is measured from. Frames not newer than the last are ignored.
  void update(const perception::MotionResult& motion, const Eigen::Matrix3d& R_WC,
              std::int64_t stamp_ns, const perception::FixatedRegion& region = {},
              perception::PixelPoint fixation = {}) noexcept;

  /// The target's unit direction at `t_ns`, extrapolated from the last frame with the filtered
  /// angular velocity.
  Eigen::Vector3d direction_W(std::int64_t t_ns) const noexcept;
  /// Filtered angular velocity of the target's direction (rad/s, base frame).
  const Eigen::Vector3d& angular_velocity_W() const { return angular_velocity_W_; }

  bool active() const { return active_; }
  std::uint64_t measured_frames() const { return measured_frames_; }
  std::uint64_t extrapolated_frames() const { return extrapolated_frames_; }
  /// Frames whose motion was measured along one direction only, completed across it by the
  /// fixated region's centre.
  std::uint64_t region_frames() const { return region_frames_; }

  /// The share of the way from the prediction to the region's centre taken each frame: the
  /// region's centre jitters by a cell's part as cells join and leave it, the prediction carries
  /// the velocity learnt so far (an alpha-beta filter across the stripes).
  static constexpr double kRegionGain = 0.5;
  /// A region of fewer than 1/this or more than this many cells than at the start is another
  /// part of the object (a curved one: only the part at the vergence depth matches) or more
  /// than the object: its centre is not the target's.
  static constexpr double kRegionCellsRatio = 1.5;

 private:
  /// `direction` turned by `angular_velocity * dt_s` (Rodrigues).
  static Eigen::Vector3d turned(const Eigen::Vector3d& direction,
                                const Eigen::Vector3d& angular_velocity, double dt_s) noexcept;

  /// The target's normalised image position with the motion's unmeasured component taken from
  /// `fallback` (a unit vector along the window's weakest structure).
  /// The region's centre, normalised image coordinates; nullopt-like: false when unusable.
  bool region_centre(const perception::FixatedRegion& region, perception::PixelPoint fixation,
                     Eigen::Vector2d& centre) const noexcept;
  /// Whether `region` is the same part of the object as the one the offset was fixed on.
  bool region_like_start(const perception::FixatedRegion& region) const noexcept;
  static Eigen::Vector2d completed(const Eigen::Vector2d& measured, const Eigen::Vector2d& fallback,
                                   double gradient_orientation_rad) noexcept;

  double fx_px_;
  double fy_px_;
  double cx_px_;
  double cy_px_;
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
  std::uint64_t region_frames_ = 0;
  /// The region's centre less the target's position (normalised), fixed the first frame after
  /// start() that has a region.
  bool have_region_offset_ = false;
  int region_cells_ = 0;  ///< The region's size when the offset was fixed.
  Eigen::Vector2d region_offset_ = Eigen::Vector2d::Zero();
};

}  // namespace cambio::control
