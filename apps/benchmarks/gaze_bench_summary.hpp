#pragma once

// What `cambio gaze-bench` makes of its runs' scores: per task the success rate, the times to
// verge and the errors (medians, 95th percentiles, worst), the failures and why; overall, the
// disparity confidence's calibration (how often a measurement of each confidence was right).

#include <cstdint>
#include <vector>

#include "json_output.hpp"

namespace cambio::app {

/// The summary of `results` (the runs' JSON as gaze_bench_runs.hpp gives it): "seed",
/// "scenes_per_task", "tasks" (those that had runs) and "confidence_calibration" (ten bins).
Json summarise_gaze_bench(const std::vector<Json>& results, std::uint64_t seed, int scenes);

/// The summary as a table for people, on stdout.
void print_gaze_bench_table(const Json& summary);

}  // namespace cambio::app
