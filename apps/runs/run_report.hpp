#pragma once

// What `cambio run` prints once the job has run: the loops' statistics and time shares, the
// cameras, joint loop and CAN groups' counts, what the perception and the behaviour did, and a
// warning for each loop that allocated without declaring it.

#include "main_job_result.hpp"

namespace cambio::app {

/// The figures on stdout; a failed behaviour's error on stderr.
void print_run_report(const MainJobResult& result);

/// One warning on stderr per loop that allocated in update() without declaring it.
void warn_allocating_loops(const MainJobResult& result);

}  // namespace cambio::app
