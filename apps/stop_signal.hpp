#pragma once

#include <atomic>

namespace cambio::app {

/// Installs SIGINT, SIGTERM and SIGHUP handlers that set the returned flag (async-signal-safe),
/// so executors finish their cycle, deactivate their loops and backends, and the command writes
/// what it has before exiting. A second signal while stopping never ends the program before the
/// drives are quick-stopped and disabled: it asks the command to hurry (stop_hurried()), skipping
/// what is optional (plots, key frames); the results and the summary are still written.
const std::atomic<bool>& install_stop_signal_handlers();

/// A second stop signal arrived: skip optional work on the way out.
bool stop_hurried();

/// The signal that stopped the run (0 if none).
int stop_signal_number();

/// The exit status for a run stopped by `signal_number`: 130 for SIGINT, 143 for SIGTERM and for
/// SIGHUP (a closed terminal is a request to terminate), 128 + n otherwise.
int exit_status_for_signal(int signal_number);

}  // namespace cambio::app
