// `cambio run EXPERIMENT.yaml`: the main job (main_job.hpp) with its report. The run and its
// report are in runs/experiment_run.hpp.
#include <iostream>
#include <memory>
#include <optional>

#include "argument_parser.hpp"
#include "cambio/can/can_traffic_log.hpp"
#include "command.hpp"
#include "config_errors.hpp"
#include "experiment_run.hpp"
#include "output_directory.hpp"
#include "stop_signal.hpp"

namespace cambio::app {

int run_run_command(std::span<const std::string> args) {
  ArgumentParser parser("run", "EXPERIMENT.yaml [--set KEY=VALUE]... [--out DIR]");
  parser.positional("EXPERIMENT.yaml", "the experiment to run (firmware_config/experiments/)")
      .repeated_option("set", "KEY=VALUE",
                       "override an experiment key (experiment.duration_s=2) or, prefixed with "
                       "rig., a rig key (rig.loops.control.rate_hz=100)")
      .option("out", "DIR", "write each camera's last frame (PNG) and summary.json here")
      .option("can-log", "FILE",
              "log every CAN frame of the socketcan groups' buses to FILE in candump -L format "
              "(replay with canplayer -I FILE); written beside FILE and put in place when the "
              "run ends, so a run that never starts leaves FILE as it was (its frames in "
              "FILE.incomplete)");
  if (!parser.parse(args)) return kExitOk;
  // First: building configures the drives (SDO on a CAN rig), and a signal then must be heard,
  // never kill the program silently.
  const auto& stop = install_stop_signal_handlers();

  std::optional<config::ExperimentConfig> loaded =
      load_experiment_or_report(*parser.positional_value("EXPERIMENT.yaml"), parser.values("set"));
  if (!loaded) return kExitBadInput;
  config::ExperimentConfig& experiment = *loaded;

  // The destination is checked and claimed before any work: a bad --out fails at once.
  std::optional<OutputDirectory> out;
  if (parser.has("out")) out.emplace(parser.value("out"), "run");

  std::unique_ptr<can::CanTrafficLog> can_log;
  if (parser.has("can-log")) {
    try {
      can_log = std::make_unique<can::CanTrafficLog>(parser.value("can-log"));
    } catch (const std::runtime_error& error) {
      std::cerr << "cambio run: --can-log: " << error.what() << "\n";
      return kExitBadInput;
    }
  }
  return run_experiment(experiment, can_log.get(), out ? &*out : nullptr, stop);
}

}  // namespace cambio::app
