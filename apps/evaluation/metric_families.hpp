#pragma once

// Internal to cambio_evaluation: compute_metrics in steps, one per family of metrics (their
// definitions are in run_metrics.hpp). Each sets its metrics in `out`, or marks them absent with
// the reason.

#include <cstddef>

#include "metrics_builder.hpp"
#include "scored_trace.hpp"

namespace cambio::app::detail {

// gaze_metrics.cpp
/// final_disparity_px, true_gaze_error_deg.
void final_gaze_metrics(const ScoredTrace& scored, MetricsBuilder& out);
/// settle_time_s, max_verging_gaze_error_visible_deg. Returns the first row that meets the
/// settle thresholds (rows.size(): none), where fixation_belief_metrics starts.
std::size_t settle_metrics(const ScoredTrace& scored, MetricsBuilder& out);
/// pursuit_rms_error_deg.
void pursuit_metrics(const ScoredTrace& scored, MetricsBuilder& out);
/// final_max_abs_eye_pan_deg.
void eye_pan_metrics(const ScoredTrace& scored, MetricsBuilder& out);
/// target_occluded_s.
void occlusion_metrics(const ScoredTrace& scored, MetricsBuilder& out);

// saccade_metrics.cpp
/// saccade_duration_s, max_vergence_error_during_saccade_deg, reverge_time_s.
void saccade_metrics(const ScoredTrace& scored, MetricsBuilder& out);

// belief_metrics.cpp
/// max_believed_vs_true_joint_error_rad.
void joint_belief_metrics(const ScoredTrace& scored, MetricsBuilder& out);
/// final_ and max_believed_vs_true_fixation_error_m, over the rows from first_settled on.
void fixation_belief_metrics(const ScoredTrace& scored, std::size_t first_settled,
                             MetricsBuilder& out);

// object_visits.cpp
/// objects_visited, all_objects_visited_s.
void visit_metrics(const ScoredTrace& scored, MetricsBuilder& out);

// reach_metrics.cpp
/// time_to_touch_s, touch_position_error_m, estimated_target_error_m.
void reach_metrics(const ScoredTrace& scored, MetricsBuilder& out);

}  // namespace cambio::app::detail
