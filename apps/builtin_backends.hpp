#pragma once

#include "cambio/config/experiment_config.hpp"
#include "cambio/hal/backend_factory.hpp"

namespace cambio::app {

/// Registers every backend this build of `cambio` carries, with what only that backend needs
/// taken from the experiment (the sim: the rig file's world description and the scene), and
/// declares the ones it does not carry (socketcan, until its drivers land) so a rig naming them
/// is refused with the reason. Throws config::ConfigError for a bad scene file.
void register_builtin_backends(hal::BackendFactory& factory,
                               const config::ExperimentConfig& experiment);

}  // namespace cambio::app
