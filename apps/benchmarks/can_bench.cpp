#include "can_bench.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <iostream>
#include <memory>
#include <string>
#include <vector>

#include "cambio/canopen/can_bus_load.hpp"
#include "cambio/canopen/can_rig_from_config.hpp"
#include "cambio/config/hardware_description.hpp"
#include "cambio/config/rig_loader.hpp"
#include "cambio/config/shipped_config.hpp"
#include "can_bench_rig.hpp"
#include "can_pdo_throughput.hpp"
#include "command.hpp"
#include "json_output.hpp"
#include "peak_rss.hpp"

namespace cambio::app {

namespace {

/// The upper middle sample for an even count.
double median(std::vector<double> values) {
  std::nth_element(values.begin(), values.begin() + static_cast<std::ptrdiff_t>(values.size() / 2),
                   values.end());
  return values[values.size() / 2];
}

double percentile(std::vector<double> values, double p) {
  std::sort(values.begin(), values.end());
  const auto index =
      static_cast<std::size_t>(std::ceil(p * static_cast<double>(values.size()))) - 1;
  return values[std::min(index, values.size() - 1)];
}

/// The master's cycle per rig and the PDO rate, one sample of each per round.
struct RoundFigures {
  std::vector<std::vector<double>> p50_us, p99_us;  ///< Per rig, per round.
  std::vector<double> pdo_rates;
};

/// Rounds of `cycles` cycles on each rig in turn, then the PDO loop.
RoundFigures time_rounds(const std::vector<std::unique_ptr<MasterAndDrives>>& rigs, int cycles,
                         int rounds) {
  RoundFigures figures;
  figures.p50_us.resize(rigs.size());
  figures.p99_us.resize(rigs.size());
  std::vector<double> samples(static_cast<std::size_t>(cycles));
  const long long frame_pairs = 200LL * cycles;
  (void)pdo_frames_per_s(frame_pairs / 10);  // Warm-up.
  for (int round = 0; round < rounds; ++round) {
    for (std::size_t r = 0; r < rigs.size(); ++r) {
      for (int i = 0; i < cycles; ++i) samples[static_cast<std::size_t>(i)] = rigs[r]->cycle();
      figures.p50_us[r].push_back(percentile(samples, 0.50));
      figures.p99_us[r].push_back(percentile(samples, 0.99));
    }
    figures.pdo_rates.push_back(pdo_frames_per_s(frame_pairs));
  }
  return figures;
}

struct BusLoadFigures {
  std::string rig;
  std::string bus;
  double rate_hz = 0.0;
  std::uint64_t frames = 0;
  double measured = 0.0;  ///< Fraction of the bus's bit rate.
  double model = 0.0;
  canopen::CanGroupCounters counters;
};

/// The shipped pan-tilt on socketcan at its 1 kHz, every frame on the bus counted (RPDOs, SYNC,
/// TPDOs, heartbeats, anything else) over `cycles` cycles of simulated time.
BusLoadFigures measure_pan_tilt_bus_load(int cycles) {
  config::RigConfig pan_tilt =
      config::load_rig(config::resolve_config_argument("rigs", "pan_tilt"),
                       {{"groups.pan_tilt.backend", canopen::SocketCanBackend::kName}});
  MasterAndDrives pan_tilt_bus(pan_tilt);
  const WireCount before = pan_tilt_bus.wire();
  for (int i = 0; i < cycles; ++i) (void)pan_tilt_bus.cycle();
  const WireCount& after = pan_tilt_bus.wire();
  const canopen::CanRigInfo pan_tilt_can = canopen::can_rig_from_config(pan_tilt);
  const canopen::CanBusInfo& bus = pan_tilt_can.buses.front();
  const double window_s =
      static_cast<double>(cycles) * static_cast<double>(pan_tilt_bus.period_ns()) * 1e-9;
  BusLoadFigures figures;
  figures.rig = pan_tilt.name;
  figures.bus = bus.name;
  figures.rate_hz = pan_tilt.groups.front().rate_hz;
  figures.frames = after.frames - before.frames;
  figures.measured = static_cast<double>(after.bits - before.bits) / window_s /
                     static_cast<double>(bus.bitrate_bit_s);
  figures.model = canopen::can_bus_load(config::hardware_description(pan_tilt), pan_tilt_can, bus,
                                        canopen::SocketCanBackend::kName)
                      .load;
  figures.counters = pan_tilt_bus.group().counters();
  return figures;
}

void print_json(const CanBenchOptions& options, const std::vector<int>& drive_counts,
                const RoundFigures& rounds, const BusLoadFigures& load, long rss_kib) {
  Json cycle_us = Json::object();
  for (std::size_t r = 0; r < drive_counts.size(); ++r) {
    cycle_us[std::to_string(drive_counts[r])] = {
        {"p50", as_printed(median(rounds.p50_us[r]), "%.3g")},
        {"p99", as_printed(median(rounds.p99_us[r]), "%.3g")}};
  }
  const Json figures = {
      {"bus", "in-process (host)"},
      {"emulated", false},
      {"rounds", options.rounds},
      {"cycles_per_round", options.cycles},
      {"pdo_frames_per_s_per_core", as_printed(median(rounds.pdo_rates), "%.3g")},
      {"master_cycle_us", cycle_us},
      {"bus_load_rig", load.rig},
      {"bus_load_bus", load.bus},
      {"bus_load_rate_hz", load.rate_hz},
      {"bus_load_frames", load.frames},
      {"bus_load_measured", as_printed(load.measured, "%.4f")},
      {"bus_load_model", as_printed(load.model, "%.4f")},
      {"bus_load_missed_sync_answers", load.counters.missed_sync_answers},
      {"peak_rss_kib", rss_kib},
  };
  std::cout << json_text(figures);
}

void print_table(const CanBenchOptions& options, const std::vector<int>& drive_counts,
                 const RoundFigures& rounds, const BusLoadFigures& load, long rss_kib) {
  std::printf("cambio can-bench: in-process bus (host), medians of %d alternating rounds\n",
              options.rounds);
  std::printf("  PDO frames packed+unpacked  %12.3g /s per core\n", median(rounds.pdo_rates));
  for (std::size_t r = 0; r < drive_counts.size(); ++r) {
    std::printf("  master cycle, %2d drives     p50 %8.2f us   p99 %8.2f us\n", drive_counts[r],
                median(rounds.p50_us[r]), median(rounds.p99_us[r]));
  }
  std::printf("  bus load, %s %s at %g Hz: measured %.2f %%, model %.2f %% (%d cycles)\n",
              load.rig.c_str(), load.bus.c_str(), load.rate_hz, 100.0 * load.measured,
              100.0 * load.model, options.cycles);
  std::printf("  peak RSS                    %12ld KiB\n", rss_kib);
}

}  // namespace

int run_can_bench(const CanBenchOptions& options) {
  // The master's cycle, 2, 5 and 10 drives, one round of each in turn; the rigs live to the end
  // of the bench, whose peak RSS is reported.
  const std::vector<int> drive_counts = {2, 5, 10};
  std::vector<std::unique_ptr<MasterAndDrives>> rigs;
  for (const int drives : drive_counts) {
    rigs.push_back(std::make_unique<MasterAndDrives>(can_bench_rig(drives)));
  }
  const RoundFigures rounds = time_rounds(rigs, options.cycles, options.rounds);
  const BusLoadFigures load = measure_pan_tilt_bus_load(options.cycles);
  const long rss_kib = peak_rss_kib();
  if (options.json) {
    print_json(options, drive_counts, rounds, load, rss_kib);
  } else {
    print_table(options, drive_counts, rounds, load, rss_kib);
  }
  return kExitOk;
}

}  // namespace cambio::app
