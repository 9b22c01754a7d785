#pragma once

// `cambio console`'s run: the experiment's loops running in the background (the main job on the
// built-in backends, without its script or trace) while console_session.hpp carries out the
// lines read from standard input (console_input.hpp).

#include <string>
#include <vector>

#include "cambio/config/experiment_config.hpp"

namespace cambio::app {

/// Runs the console on `experiment` (one without a behaviour) until `quit`, the end of input or
/// a stop signal, and returns the exit status. `real_time_factor`: simulated seconds per wall
/// second on the lockstep executor, 0 for as fast as the loops go.
int run_console(const config::ExperimentConfig& experiment, double real_time_factor);

/// As run_console, with `script`'s lines instead of standard input, as fast as the loops go on
/// the lockstep executor; ends after the last line. Exit status as run_console's, 2 when a line
/// was refused.
int run_console_script(const config::ExperimentConfig& experiment, std::vector<std::string> script);

}  // namespace cambio::app
