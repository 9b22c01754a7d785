#pragma once

// `cambio run`'s summary.json: how the run ended, what every loop, device and the perception,
// gaze, behaviour and arms did, and (with a trace) the metrics and goals.

#include <optional>

#include "cambio/config/experiment_config.hpp"
#include "json_output.hpp"
#include "main_job_result.hpp"
#include "run_evaluation.hpp"
#include "run_outcome.hpp"

namespace cambio::app {

/// The summary; `trace` and `evaluation` may be absent (a rig without a sim or a stereo pair).
Json summary_json(const config::ExperimentConfig& experiment, const MainJobResult& result,
                  const RunOutcome& outcome, const Trace* trace,
                  const std::optional<RunEvaluation>& evaluation);

}  // namespace cambio::app
