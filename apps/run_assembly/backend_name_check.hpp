#pragma once

#include "cambio/config/rig_config.hpp"
#include "cambio/hal/backend_factory.hpp"

namespace cambio::app {

/// Checks that every backend the rig names (its groups', cameras' and touch sensors') is one
/// `factory` can make, before anything is built. Throws config::ConfigError with one issue per
/// unknown name, at the rig's `backend:` key, saying which names this build carries.
void check_backend_names(const config::RigConfig& rig, const hal::BackendFactory& factory);

}  // namespace cambio::app
