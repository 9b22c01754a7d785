#pragma once

// Internal to cambio_evaluation: where the eyes truly look, for the TraceRecorder's rows
// (TraceRow's true gaze errors, true disparity, occlusion and fixation).

#include <array>

#include <Eigen/Geometry>

#include "trace_recorder.hpp"

namespace cambio::app::detail {

inline std::array<double, 3> to_array(const Eigen::Vector3d& p) {
  return {p.x(), p.y(), p.z()};
}

inline Eigen::Vector3d to_vector(const std::array<double, 3>& p) {
  return {p[0], p[1], p[2]};
}

/// The eyes' true camera poses (world frame) with their optical centres and axes (unit z).
struct TrueEyes {
  Eigen::Isometry3d X_WD;  ///< The dominant eye's camera.
  Eigen::Isometry3d X_WV;  ///< The verging eye's camera.
  Eigen::Vector3d o_d, axis_d;
  Eigen::Vector3d o_v, axis_v;
};

/// Reads both cameras' poses from the ground truth (the dominant eye's first).
TrueEyes true_eyes(const TraceSources& sources);

/// Sets the row's gaze errors, true disparity, target_occluded and axis_object against the
/// dominant eye's target point target_W (NaN: none). Returns where the dominant eye's true axis
/// meets the scene.
sim::RayHit record_true_gaze(TraceRow& row, const TrueEyes& eyes, const Eigen::Vector3d& target_W,
                             const TraceSources& sources);

/// Sets the row's believed fixation (from `status`, when the row has one) and true fixation, and
/// the distance between them.
void record_fixation(TraceRow& row, const control::GazeStatus& status, const TrueEyes& eyes);

}  // namespace cambio::app::detail
