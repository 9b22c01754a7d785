#include "builtin_backends.hpp"

#include "cambio/sim/sim_backend.hpp"

namespace cambio::app {

void register_builtin_backends(hal::BackendFactory& factory) {
  sim::register_sim_backend(factory);
}

}  // namespace cambio::app
