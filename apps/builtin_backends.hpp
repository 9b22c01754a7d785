#pragma once

#include "cambio/hal/backend_factory.hpp"

namespace cambio::app {

/// Registers every backend this build of `cambio` carries (today: sim). A rig naming another
/// backend (socketcan, until its drivers land) is refused by the factory with a clear message.
void register_builtin_backends(hal::BackendFactory& factory);

}  // namespace cambio::app
