#pragma once

namespace cambio::app {

/// The process's peak resident set size so far, KiB (getrusage's ru_maxrss on Linux).
long peak_rss_kib();

}  // namespace cambio::app
