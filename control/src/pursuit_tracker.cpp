#include "cambio/control/pursuit_tracker.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <stdexcept>

namespace cambio::control {
namespace {

/// How much faster than predicted a pursued target may turn (its direction seen from the eye)
/// between two frames: a target at rest that starts at 45 deg/s, faster than the pursuit the
/// stack is built for, still passes.
constexpr double kMaxSurpriseSpeedRadPerS = 45.0 * std::numbers::pi / 180.0;

}  // namespace

PursuitTracker::PursuitTracker(const hal::CameraIntrinsics& intrinsics, double velocity_filter_s)
    : fx_px_(intrinsics.focal_x_px),
      fy_px_(intrinsics.focal_y_px),
      cx_px_(intrinsics.principal_x_px),
      cy_px_(intrinsics.principal_y_px),
      velocity_filter_s_(velocity_filter_s) {
  if (!(fx_px_ > 0.0 && fy_px_ > 0.0)) {
    throw std::invalid_argument("pursuit: the dominant camera's focal lengths must be > 0");
  }
  if (!(velocity_filter_s > 0.0)) {
    throw std::invalid_argument("pursuit: velocity_filter_s must be > 0");
  }
}

void PursuitTracker::start(const Eigen::Vector3d& direction_W, const Eigen::Matrix3d& R_WC,
                           std::int64_t stamp_ns, const perception::FixatedRegion& region,
                           perception::PixelPoint fixation) noexcept {
  const double norm = direction_W.norm();
  if (!(norm > 0.0) || !std::isfinite(norm)) return;
  direction_W_ = direction_W / norm;
  R_WC_ = R_WC;
  stamp_ns_ = stamp_ns;
  angular_velocity_W_.setZero();
  have_key_ = false;
  last_frame_ = 0;
  // The target is on the axis (normalised position 0) where the region was measured.
  have_region_offset_ = region_centre(region, fixation, region_offset_);
  region_cells_ = region.cells;
  active_ = true;
}

bool PursuitTracker::region_centre(const perception::FixatedRegion& region,
                                   perception::PixelPoint fixation,
                                   Eigen::Vector2d& centre) const noexcept {
  // A clipped region's centre moves with the window, not the object.
  if (!region.valid || region.clipped) return false;
  centre = Eigen::Vector2d((fixation.x + region.centroid_x_px - cx_px_) / fx_px_,
                           (fixation.y + region.centroid_y_px - cy_px_) / fy_px_);
  return centre.allFinite();
}

bool PursuitTracker::region_like_start(const perception::FixatedRegion& region) const noexcept {
  return region.cells * kRegionCellsRatio >= region_cells_ &&
         region.cells <= kRegionCellsRatio * region_cells_;
}

Eigen::Vector2d PursuitTracker::completed(const Eigen::Vector2d& measured,
                                          const Eigen::Vector2d& fallback,
                                          double gradient_orientation_rad) noexcept {
  // Along the strongest gradient the motion is measured; across it (along the stripes or the
  // edge) it is the estimator's prior, replaced by the fallback's position.
  const Eigen::Vector2d across(-std::sin(gradient_orientation_rad),
                               std::cos(gradient_orientation_rad));
  return measured + across * across.dot(fallback - measured);
}

Eigen::Vector3d PursuitTracker::turned(const Eigen::Vector3d& direction,
                                       const Eigen::Vector3d& angular_velocity,
                                       double dt_s) noexcept {
  const Eigen::Vector3d rotation = angular_velocity * dt_s;
  const double angle = rotation.norm();
  if (angle < 1e-12) return direction;
  return Eigen::AngleAxisd(angle, rotation / angle) * direction;
}

void PursuitTracker::update(const perception::MotionResult& motion, const Eigen::Matrix3d& R_WC,
                            std::int64_t stamp_ns, const perception::FixatedRegion& region,
                            perception::PixelPoint fixation) noexcept {
  if (!active_ || stamp_ns <= stamp_ns_) return;
  const double dt_s = static_cast<double>(stamp_ns - stamp_ns_) * 1e-9;
  Eigen::Vector3d direction = turned(direction_W_, angular_velocity_W_, dt_s);
  // The prediction seen from this frame's camera, and the region's word on the target there.
  const Eigen::Vector3d predicted_C = R_WC.transpose() * direction;
  const bool predicted_seen = predicted_C.z() > 1e-6;
  const Eigen::Vector2d predicted_xy =
      predicted_seen ? Eigen::Vector2d(predicted_C.head<2>() / predicted_C.z())
                     : Eigen::Vector2d::Zero();
  Eigen::Vector2d region_xy = Eigen::Vector2d::Zero();
  bool region_seen = predicted_seen && region_centre(region, fixation, region_xy);
  if (region_seen && !have_region_offset_) {
    region_offset_ = region_xy - predicted_xy;
    region_cells_ = region.cells;
    have_region_offset_ = true;
  }
  region_seen = region_seen && region_like_start(region);
  region_xy -= region_offset_;
  // The target's normalised image position in the previous frame, moved by the measured flow.
  const Eigen::Vector3d before_C = R_WC_.transpose() * direction_W_;
  const bool seen_before = before_C.z() > 1e-6;
  // A key frame the tracker saw: the target's position there is the one it then believed.
  const bool key_usable = motion.key_valid && std::isfinite(motion.key_flow_x_px) &&
                          std::isfinite(motion.key_flow_y_px);
  if (key_usable && seen_before && motion.key_frame != key_frame_ &&
      motion.key_frame == last_frame_) {
    key_xy_ = Eigen::Vector2d(before_C.x() / before_C.z(), before_C.y() / before_C.z());
    key_frame_ = motion.key_frame;
    have_key_ = true;
  }
  last_frame_ = motion.frame;
  const bool from_key = key_usable && have_key_ && motion.key_frame == key_frame_;
  const bool from_flow = motion.valid && !motion.fixation_changed && seen_before &&
                         std::isfinite(motion.flow_x_px) && std::isfinite(motion.flow_y_px);
  if (from_key || from_flow) {
    double x = 0.0;
    double y = 0.0;
    if (from_key) {
      x = key_xy_.x() + static_cast<double>(motion.key_flow_x_px) / fx_px_;
      y = key_xy_.y() + static_cast<double>(motion.key_flow_y_px) / fy_px_;
    } else {
      x = before_C.x() / before_C.z() + static_cast<double>(motion.flow_x_px) / fx_px_;
      y = before_C.y() / before_C.z() + static_cast<double>(motion.flow_y_px) / fy_px_;
    }
    // Measured along one direction only: the other from the region, else the prediction.
    if (motion.one_directional) {
      const Eigen::Vector2d xy = completed(
          {x, y},
          region_seen ? Eigen::Vector2d(predicted_xy + kRegionGain * (region_xy - predicted_xy))
                      : predicted_xy,
          motion.gradient_orientation_rad);
      if (region_seen) ++region_frames_;
      x = xy.x();
      y = xy.y();
    }
    const Eigen::Vector3d measured_direction = (R_WC * Eigen::Vector3d(x, y, 1.0)).normalized();
    // A measurement that would need the target to move much faster than predicted is a false
    // motion estimate (the fovea's window taken by the surround), not the target: extrapolate.
    const double surprise_rad =
        std::atan2(direction.cross(measured_direction).norm(), direction.dot(measured_direction));
    if (surprise_rad > kMaxSurpriseSpeedRadPerS * dt_s) {
      ++extrapolated_frames_;
      direction_W_ = direction;
      R_WC_ = R_WC;
      stamp_ns_ = stamp_ns;
      return;
    }
    direction = measured_direction;
    // The angular velocity that turned the old direction into the new one, low-pass filtered.
    const Eigen::Vector3d axis = direction_W_.cross(direction);
    const double sine = axis.norm();
    const double angle = std::atan2(sine, direction_W_.dot(direction));
    const Eigen::Vector3d measured =
        sine > 1e-12 ? Eigen::Vector3d(axis / sine * angle / dt_s) : Eigen::Vector3d::Zero();
    const double alpha = dt_s / (velocity_filter_s_ + dt_s);
    angular_velocity_W_ += alpha * (measured - angular_velocity_W_);
    ++measured_frames_;
  } else {
    ++extrapolated_frames_;
  }
  direction_W_ = direction;
  R_WC_ = R_WC;
  stamp_ns_ = stamp_ns;
}

Eigen::Vector3d PursuitTracker::direction_W(std::int64_t t_ns) const noexcept {
  return turned(direction_W_, angular_velocity_W_, static_cast<double>(t_ns - stamp_ns_) * 1e-9);
}

}  // namespace cambio::control
