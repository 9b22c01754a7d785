#pragma once

#include <optional>
#include <string>
#include <vector>

#include "cambio/config/experiment_config.hpp"
#include "cambio/config/rig_loader.hpp"

namespace cambio::app {

/// Loads a rig; on a ConfigError prints every issue (one per line, file:line:col first) to
/// stderr and returns nullopt, so the command exits with kExitBadInput.
std::optional<config::RigConfig> load_rig_or_report(
    const std::string& path, const std::vector<config::ConfigOverride>& overrides);

/// Loads an experiment with its command line's `--set KEY=VALUE` texts applied (experiment keys,
/// or rig keys prefixed with rig.); on any problem, every malformed override or every issue of
/// the files, prints them (as report_config_error) and returns nullopt, so the command exits with
/// kExitBadInput.
std::optional<config::ExperimentConfig> load_experiment_or_report(
    const std::string& path, const std::vector<std::string>& set_texts);

/// Parses every `--set KEY.PATH=VALUE`; when any is malformed, prints all their issues (as
/// report_config_error) and returns nullopt, so the command exits with kExitBadInput.
std::optional<std::vector<config::ConfigOverride>> parse_overrides_or_report(
    const std::vector<std::string>& texts);

/// Prints each issue of a ConfigError on its own line to stderr.
void report_config_error(const config::ConfigError& error);

}  // namespace cambio::app
