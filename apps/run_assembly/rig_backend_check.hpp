#pragma once

#include "cambio/config/rig_config.hpp"
#include "cambio/hal/backend_factory.hpp"

namespace cambio::app {

/// The checks a rig passes against the backends `factory` carries before anything is built:
/// every backend the rig names (its groups', cameras' and touch sensors') is one `factory` can
/// make (else the issue is at the rig's `backend:` key, saying which names this build carries),
/// and every registered backend's own check of its settings passes (hal::BackendFactory::check;
/// each problem located at the rig key it names). Throws config::ConfigError with every issue.
void check_rig_backends(const config::RigConfig& rig, const hal::BackendFactory& factory);

}  // namespace cambio::app
