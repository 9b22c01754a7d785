// `cambio loop-bench`: how punctual can loops be on this machine? Runs the realtime executor with
// loops that do no work and reports wake-up latency percentiles, overruns and allocations, so a
// user can choose loop rates (and compare with cyclictest run beside it).
#include <unistd.h>

#include <algorithm>
#include <iostream>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "argument_parser.hpp"
#include "cambio/config/rig_loader.hpp"
#include "cambio/runtime/realtime_executor.hpp"
#include "command.hpp"
#include "config_errors.hpp"
#include "controller_params.hpp"
#include "json_output.hpp"
#include "stop_signal.hpp"

namespace cambio::app {
namespace {

class IdleLoop final : public hal::Loop {
 public:
  explicit IdleLoop(std::string name) : name_(std::move(name)) {}
  const std::string& name() const override { return name_; }
  hal::Status update(const hal::LoopTick&) noexcept override { return hal::Status::kOk; }

 private:
  std::string name_;
};

}  // namespace

int run_loop_bench_command(std::span<const std::string> args) {
  ArgumentParser parser("loop-bench", "[--config RIG] [--rate-hz HZ] [--duration-s S] [--json]");
  parser.option("config", "RIG", "run the loops defined in this rig file (rates, priorities, CPUs)")
      .repeated_option("set", "KEY=VALUE", "override a rig key, e.g. loops.joint.rate_hz=500")
      .option("rate-hz", "HZ",
              "without --config: one loop at this rate, up to 100000 (default 1000)")
      .option("priority", "N",
              "without --config: SCHED_FIFO priority 1 to 99, 0 for none (default 80)")
      .option("cpu", "N", "without --config: pin the loop to this CPU, -1 for any (default: any)")
      .option("duration-s", "S", "how long to run, up to 36000 (default 10)")
      .flag("no-lock-memory", "do not mlockall (default: lock, as cyclictest -m)")
      .flag("json", "print one JSON object: {\"loops\": [...], ...}");
  if (!parser.parse(args)) return kExitOk;

  const double duration_s =
      parser.number("duration-s", 10.0, config::Range{0.0, 36'000.0, true, false},
                    "at most ten hours: the latency histogram's 32-bit counts fill at 4.29e9 "
                    "wake-ups, 11.9 h at 100 kHz");
  if (parser.has("config") &&
      (parser.has("rate-hz") || parser.has("priority") || parser.has("cpu"))) {
    throw UsageError(
        "loop-bench: --rate-hz, --priority and --cpu describe a single loop; with --config the "
        "rig's loops are used (change them with --set loops.<name>.rate_hz=...)");
  }
  if (!parser.has("config") && parser.has("set")) {
    throw UsageError("loop-bench: --set needs --config");
  }

  std::vector<config::LoopConfig> schedules;
  if (parser.has("config")) {
    std::vector<config::ConfigOverride> overrides;
    for (const auto& text : parser.values("set")) overrides.push_back(config::parse_override(text));
    const auto rig = load_rig_or_report(parser.value("config"), overrides);
    if (!rig) return kExitBadInput;
    schedules = rig->loops;
  } else {
    config::LoopConfig loop;
    loop.name = "loop";
    loop.rate_hz = parser.number("rate-hz", 1000.0, config::Range{0.0, 100'000.0, true, false},
                                 "the rig's bounds for loops.<name>.rate_hz");
    loop.priority = static_cast<int>(
        parser.integer("priority", 80, config::Range::closed(0, 99),
                       "SCHED_FIFO priorities are 1 to 99; 0 runs without real-time priority"));
    const long cpus = std::max(1L, ::sysconf(_SC_NPROCESSORS_CONF));
    loop.cpu = static_cast<int>(
        parser.integer("cpu", -1, config::Range::closed(-1, static_cast<double>(cpus - 1)),
                       "this machine's CPUs are 0 to " + std::to_string(cpus - 1) +
                           "; -1 lets the loop run on any"));
    schedules.push_back(loop);
  }

  const bool json = parser.flag_set("json");
  runtime::RealtimeExecutor executor(
      {}, {.lock_memory = !parser.flag_set("no-lock-memory"), .print_warnings = !json});
  std::vector<IdleLoop> loops;
  loops.reserve(schedules.size());
  for (const auto& schedule : schedules) {
    loops.emplace_back(schedule.name);
    executor.add_loop({&loops.back(), schedule_of(schedule)});
  }

  const auto& stop = install_stop_signal_handlers();
  if (!json) {
    std::cerr << "loop-bench: running " << schedules.size() << " loop(s) for " << duration_s
              << " s (Ctrl-C stops early)\n";
  }
  executor.run(stop, static_cast<std::int64_t>(duration_s * 1e9));

  const auto& stats = executor.statistics();
  if (json) {
    Json loop_objects = Json::array();
    for (const auto& loop : stats) loop_objects.push_back(runtime::statistics_json(loop));
    const Json report = {{"duration_s", as_printed(duration_s, "%g")},
                         {"loops", loop_objects},
                         {"warnings", executor.warnings()}};
    std::cout << json_text(report);
  } else {
    std::cout << runtime::format_statistics_table(stats.data(), stats.size());
  }
  return kExitOk;
}

}  // namespace cambio::app
