#pragma once

// `cambio run`'s run: the experiment's main job (main_job.hpp) built on the built-in backends,
// run to its end or a stop signal, and reported: the figures on stdout, the evaluation of its
// trace against the experiment's goals, and the results written to the output directory.

#include <atomic>

#include "cambio/can/can_traffic_log.hpp"
#include "cambio/config/experiment_config.hpp"
#include "output_directory.hpp"

namespace cambio::app {

/// Runs `experiment` and returns the exit status. `can_log` (may be null) records the socketcan
/// groups' frames and is closed once the run has ended; `out` (may be null) receives the results.
/// `stop` is the stop signals' flag, installed before the caller read any input: a signal while
/// the drives are configured ends the run before anything is enabled. Throws OutputError when a
/// result cannot be written.
int run_experiment(const config::ExperimentConfig& experiment, can::CanTrafficLog* can_log,
                   OutputDirectory* out, const std::atomic<bool>& stop);

}  // namespace cambio::app
