#include "true_gaze.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <string>

namespace cambio::app::detail {

namespace {

constexpr double kDegPerRad = 180.0 / std::numbers::pi;

/// atan2(|a x b|, a . b): accurate at the small angles scored here, where acos loses half the
/// digits.
double angle_deg(const Eigen::Vector3d& a, const Eigen::Vector3d& b) {
  return std::atan2(a.cross(b).norm(), a.dot(b)) * kDegPerRad;
}

/// The midpoint of the shortest segment between the lines o1 + s d1 and o2 + t d2 (unit d),
/// when they converge in front of both origins (s, t > 0); false for parallel or diverging
/// axes.
bool closest_point(const Eigen::Vector3d& o1, const Eigen::Vector3d& d1, const Eigen::Vector3d& o2,
                   const Eigen::Vector3d& d2, Eigen::Vector3d& midpoint) {
  const Eigen::Vector3d w0 = o1 - o2;
  const double b = d1.dot(d2);
  const double d = d1.dot(w0);
  const double e = d2.dot(w0);
  const double denominator = 1.0 - b * b;
  if (denominator < 1e-12) return false;
  const double s = (b * e - d) / denominator;
  const double t = (e - b * d) / denominator;
  if (!(s > 0.0 && t > 0.0)) return false;
  midpoint = 0.5 * ((o1 + s * d1) + (o2 + t * d2));
  return true;
}

/// The verging eye's target point: where the dominant eye's true axis meets the scene; when it
/// meets nothing, the point of that axis closest to target_W (NaN without one).
Eigen::Vector3d verging_target_W(const TrueEyes& eyes, const sim::RayHit& hit,
                                 const Eigen::Vector3d& target_W, bool have_target) {
  if (hit.hit) return hit.p_W;
  if (have_target) {
    return eyes.o_d + std::max(0.0, (target_W - eyes.o_d).dot(eyes.axis_d)) * eyes.axis_d;
  }
  return Eigen::Vector3d::Constant(kNoValue);
}

/// The verging eye's gaze error, the true disparity and whether its view of its (finite) target
/// point is blocked.
void record_verging_eye(TraceRow& row, const TrueEyes& eyes, const Eigen::Vector3d& verging_W,
                        const sim::RayHit& hit, const TraceSources& sources) {
  row.verging_gaze_error_deg = angle_deg(eyes.axis_v, verging_W - eyes.o_v);
  const Eigen::Vector3d p_V = eyes.X_WV.inverse() * verging_W;
  if (p_V.z() > 0.0 && sources.verging_focal_px > 0.0) {
    // The point is at the dominant image's centre: the disparity is the verging image's x.
    const double x_px = sources.verging_focal_px * p_V.x() / p_V.z();
    row.true_disparity_px = sources.verging_eye_is_right ? -x_px : x_px;
  }
  row.target_occluded =
      sources.truth->segment_blocker(eyes.o_v, verging_W, hit.hit ? hit.object : std::string()).hit;
}

}  // namespace

TrueEyes true_eyes(const TraceSources& sources) {
  TrueEyes eyes;
  eyes.X_WD = sources.truth->X_WC(sources.dominant_camera);
  eyes.X_WV = sources.truth->X_WC(sources.verging_camera);
  eyes.o_d = eyes.X_WD.translation();
  eyes.axis_d = eyes.X_WD.linear().col(2);
  eyes.o_v = eyes.X_WV.translation();
  eyes.axis_v = eyes.X_WV.linear().col(2);
  return eyes;
}

sim::RayHit record_true_gaze(TraceRow& row, const TrueEyes& eyes, const Eigen::Vector3d& target_W,
                             const TraceSources& sources) {
  const bool have_target = target_W.allFinite();
  if (have_target) row.dominant_gaze_error_deg = angle_deg(eyes.axis_d, target_W - eyes.o_d);
  sim::RayHit hit = sources.truth->cast_ray(eyes.o_d, eyes.axis_d);
  const Eigen::Vector3d verging_W = verging_target_W(eyes, hit, target_W, have_target);
  if (verging_W.allFinite()) record_verging_eye(row, eyes, verging_W, hit, sources);
  const bool named = !sources.target_object.empty();
  if (named && hit.hit && hit.object != sources.target_object) row.target_occluded = true;
  if (hit.hit) {
    const auto& objects = sources.visit_objects;
    const auto it = std::find(objects.begin(), objects.end(), hit.object);
    if (it != objects.end()) row.axis_object = static_cast<int>(it - objects.begin());
  }
  row.true_gaze_error_deg = std::fmax(row.dominant_gaze_error_deg, row.verging_gaze_error_deg);
  return hit;
}

void record_fixation(TraceRow& row, const control::GazeStatus& status, const TrueEyes& eyes) {
  if (row.gaze_status && status.believed_fixation_valid) {
    row.believed_fixation_valid = true;
    row.believed_fixation_W_m = status.believed_fixation_W_m;
  }
  Eigen::Vector3d fixation_W = Eigen::Vector3d::Zero();
  if (closest_point(eyes.o_d, eyes.axis_d, eyes.o_v, eyes.axis_v, fixation_W)) {
    row.true_fixation_valid = true;
    row.true_fixation_W_m = to_array(fixation_W);
  }
  if (row.believed_fixation_valid && row.true_fixation_valid) {
    row.fixation_error_m = (to_vector(row.believed_fixation_W_m) - fixation_W).norm();
  }
}

}  // namespace cambio::app::detail
