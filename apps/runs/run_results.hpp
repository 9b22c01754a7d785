#pragma once

// What `cambio run --out DIR` writes: each camera's last frame (PNG), with a trace its files and
// plots, and summary.json, committed as a set.

#include <optional>

#include "cambio/config/experiment_config.hpp"
#include "main_job.hpp"
#include "output_directory.hpp"
#include "run_evaluation.hpp"
#include "run_outcome.hpp"

namespace cambio::app {

/// Stages the results of `job`'s finished run in `out`, commits them and says so on stderr. The
/// plots are skipped (and that said) when a second signal asked to hurry. Throws OutputError
/// when a file cannot be written.
void write_run_results(OutputDirectory& out, const config::ExperimentConfig& experiment,
                       MainJob& job, const MainJobResult& result, const RunOutcome& outcome,
                       const std::optional<RunEvaluation>& evaluation);

}  // namespace cambio::app
