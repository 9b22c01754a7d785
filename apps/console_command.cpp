// `cambio console EXPERIMENT.yaml`: the paper's standard-input commands, with the experiment's
// loops running in the background (console_session.hpp carries out each line). The run is in
// runs/console_run.hpp.
#include <iostream>
#include <optional>

#include "argument_parser.hpp"
#include "command.hpp"
#include "config_errors.hpp"
#include "console_run.hpp"

namespace cambio::app {

int run_console_command(std::span<const std::string> args) {
  ArgumentParser parser("console", "EXPERIMENT.yaml [--set KEY=VALUE]... [--rtf FACTOR]");
  parser.positional("EXPERIMENT.yaml", "the experiment whose rig and scene to drive")
      .repeated_option("set", "KEY=VALUE", "override an experiment or (rig.) rig key")
      .option("rtf", "FACTOR",
              "simulated seconds per wall second on the lockstep executor (default 1; 0: as "
              "fast as the loops go)");
  if (!parser.parse(args)) return kExitOk;
  // The parser's number rules, as every other numeric option: decimal text only (no "0x1p3",
  // no leading blank).
  const double real_time_factor =
      parser.number("rtf", 1.0, config::Range::non_negative(), "simulated seconds per wall second");
  std::optional<config::ExperimentConfig> loaded =
      load_experiment_or_report(*parser.positional_value("EXPERIMENT.yaml"), parser.values("set"));
  if (!loaded) return kExitBadInput;
  config::ExperimentConfig& experiment = *loaded;

  // A behaviour decides what the robot does; typed commands would fight it for the gaze.
  if (experiment.behaviour) {
    std::cerr << "cambio console: " << experiment.name << " runs the behaviour '"
              << experiment.behaviour->name
              << "', which commands the gaze; the console takes experiments without one\n";
    return kExitBadInput;
  }
  return run_console(experiment, real_time_factor);
}

}  // namespace cambio::app
