#pragma once

#include <atomic>

namespace cambio::app {

/// Installs SIGINT and SIGTERM handlers that set the returned flag (async-signal-safe), so
/// executors finish their cycle, deactivate their loops and report before the program exits.
/// A second signal while stopping ends the program at once.
const std::atomic<bool>& install_stop_signal_handlers();

}  // namespace cambio::app
