#pragma once

// `cambio can-bench`'s measurement: the CAN side's figures on this host, on the in-process bus
// (no kernel CAN stack involved, labelled so):
// - PDO frames packed and unpacked per second on one core (can_pdo_throughput.hpp);
// - the master's cycle cost (CanJointGroup read + write + sync) for 2, 5 and 10 CiA 402 drives,
//   p50 and p99, with the virtual rig's emulated drives answering between cycles, outside the
//   timed part (can_bench_rig.hpp);
// - the bus load the shipped pan-tilt puts on can0 at 1 kHz, counted from the frames the
//   in-process network carried (worst-case stuffed bits per frame, as the loader counts them),
//   against the bus-load model (canopen::can_bus_load);
// - the bench's own peak RSS.
// Each timed figure is the median over rounds that alternate between the cases, so a burst of
// load from another process skews one round, not the figure.

namespace cambio::app {

struct CanBenchOptions {
  int cycles = 2000;  ///< Joint-loop cycles per round and per case; >= 100 for a p99.
  int rounds = 10;    ///< Alternating rounds; the figures are their medians.
  bool json = false;  ///< One JSON object instead of a table.
};

/// Measures and prints the figures; returns the exit status. Throws std::runtime_error when the
/// emulated drives do not enable or the master's cycle fails.
int run_can_bench(const CanBenchOptions& options);

}  // namespace cambio::app
