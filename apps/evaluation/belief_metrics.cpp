// Believed against true: the joints and the fixation point (metric_families.hpp).

#include <algorithm>
#include <cmath>

#include "metric_families.hpp"

namespace cambio::app::detail {

void joint_belief_metrics(const ScoredTrace& scored, MetricsBuilder& out) {
  double joint_error = -kInfinity;
  for (const TraceJointSample& joint : scored.trace.joints) {
    const double e = std::abs(joint.believed_rad - joint.true_rad);
    if (std::isfinite(e)) joint_error = std::max(joint_error, e);
  }
  if (joint_error > -kInfinity) {
    out.set("max_believed_vs_true_joint_error_rad", joint_error);
  } else {
    out.absent("max_believed_vs_true_joint_error_rad", "no joint had both believed and true");
  }
}

void fixation_belief_metrics(const ScoredTrace& scored, std::size_t first_settled,
                             MetricsBuilder& out) {
  // From the first settled row on: with the eyes (nearly) parallel the two axes meet far away or
  // nowhere, and the distance between two such points says nothing about either.
  const auto& rows = scored.trace.rows;
  double fixation_max = -kInfinity, fixation_final = kInfinity;
  for (std::size_t k = first_settled; k < rows.size(); ++k) {
    const TraceRow& row = rows[k];
    if (!std::isfinite(row.fixation_error_m)) continue;
    fixation_max = std::max(fixation_max, row.fixation_error_m);
    fixation_final = row.fixation_error_m;
  }
  if (fixation_max > -kInfinity) {
    out.set("final_believed_vs_true_fixation_error_m", fixation_final);
    out.set("max_believed_vs_true_fixation_error_m", fixation_max);
  } else {
    const char* why = "no sample after the gaze settled had both a believed and a true fixation";
    out.absent("final_believed_vs_true_fixation_error_m", why);
    out.absent("max_believed_vs_true_fixation_error_m", why);
  }
}

}  // namespace cambio::app::detail
