#pragma once

// How `cambio console` drives the main job on each executor: on the lockstep one it decides
// every step, between lines; on the realtime one (the rig drives hardware) the loops run on
// their threads while this thread reads lines and sends commands.

#include <atomic>

#include "console_input.hpp"
#include "console_session.hpp"
#include "main_job.hpp"

namespace cambio::app {

struct ConsoleRun {
  MainJob& job;
  ConsoleSession& session;
  LineSource& lines;
  const std::atomic<bool>& signal_stop;
  double real_time_factor = 1.0;
};

/// Lockstep: the console decides each step; the simulation runs in 10 ms slices paced to the
/// wall clock at the real-time factor (0: unpaced), and stands still while a piped line is read.
MainJobResult run_console_lockstep(ConsoleRun& run);

/// Realtime (the rig drives hardware): the executor's threads run the loops; this thread reads
/// lines and sends commands, and `wait S` sleeps S seconds. Rethrows what the loops threw.
MainJobResult run_console_realtime(ConsoleRun& run);

}  // namespace cambio::app
