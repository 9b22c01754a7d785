// `cambio can-bench [--json] [--cycles N] [--rounds R]`: the CAN side's figures on this host, on
// the in-process bus: PDO frames packed and unpacked per second, the master's cycle cost for 2, 5
// and 10 drives, the shipped pan-tilt's bus load against the model, and the bench's peak RSS.
// The bench is in benchmarks/can_bench.hpp.
#include <string>

#include "argument_parser.hpp"
#include "can_bench.hpp"
#include "command.hpp"

namespace cambio::app {

int run_can_bench_command(std::span<const std::string> args) {
  ArgumentParser parser("can-bench",
                        "measure the CANopen master's cost and the bus load on the in-process bus");
  parser.option("cycles", "N", "joint-loop cycles per round and per case (default 2000)")
      .option("rounds", "R", "alternating rounds; the figures are their medians (default 10)")
      .flag("json", "print one JSON object instead of a table");
  if (!parser.parse(args)) return kExitOk;
  CanBenchOptions options;
  options.cycles = static_cast<int>(
      parser.integer("cycles", 2000, config::Range::closed(100, 1'000'000),
                     "a p99 needs at least 100 cycles; a million is minutes of run time"));
  options.rounds = static_cast<int>(parser.integer("rounds", 10, config::Range::closed(10, 1000),
                                                   "the figures are medians over >= 10 rounds"));
  options.json = parser.flag_set("json");
  return run_can_bench(options);
}

}  // namespace cambio::app
