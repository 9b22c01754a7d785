// `cambio can-bench [--json] [--cycles N] [--rounds R]`: the CAN side's figures on this host, on
// the in-process bus (no kernel CAN stack involved, labelled so):
// - PDO frames packed and unpacked per second on one core (pdo_layout's minimum set: RPDO1 and
//   TPDO1 of a CSP drive);
// - the master's cycle cost (CanJointGroup read + write + sync) for 2, 5 and 10 CiA 402 drives,
//   p50 and p99, with the virtual rig's emulated drives answering between cycles, outside the
//   timed part;
// - the bus load the shipped pan-tilt puts on can0 at 1 kHz, counted from the frames the
//   in-process network carried (worst-case stuffed bits per frame, as the loader counts them),
//   against the bus-load model (canopen::can_bus_load);
// - the bench's own peak RSS.
// Each timed figure is the median over rounds that alternate between the cases, so a burst of
// load from another process skews one round, not the figure.

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <iostream>
#include <memory>
#include <string>
#include <vector>

#include "argument_parser.hpp"
#include "cambio/can/in_process_can_bus.hpp"
#include "cambio/canopen/can_bus_load.hpp"
#include "cambio/canopen/can_rig_from_config.hpp"
#include "cambio/canopen/pdo_codec.hpp"
#include "cambio/canopen/pdo_layout.hpp"
#include "cambio/canopen/protocol.hpp"
#include "cambio/canopen/socketcan_backend.hpp"
#include "cambio/config/hardware_description.hpp"
#include "cambio/config/rig_loader.hpp"
#include "cambio/config/shipped_config.hpp"
#include "cambio/hal/manual_clock.hpp"
#include "cambio/virtual_rig/virtual_rig.hpp"
#include "command.hpp"
#include "json_output.hpp"
#include "peak_rss.hpp"

namespace cambio::app {

namespace {

using WallClock = std::chrono::steady_clock;

/// When the emulated drives handle what the master sent, after it went out.
constexpr std::int64_t kAnswerDelayNs = 100'000;

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

/// Bits a frame takes on the wire, summed over every frame any endpoint put on the network.
struct WireCount {
  std::uint64_t frames = 0;
  std::uint64_t bits = 0;
};

/// An endpoint of the bench's network, counting what it sends into a WireCount.
class CountingBus final : public hal::CanBus {
 public:
  CountingBus(hal::CanBus& bus, WireCount& count) : bus_(bus), count_(count) {}
  const std::string& name() const override { return bus_.name(); }
  hal::Status send(const hal::CanFrame& frame) override {
    const hal::Status status = bus_.send(frame);
    if (status == hal::Status::kOk) {
      ++count_.frames;
      count_.bits += static_cast<std::uint64_t>(canopen::can_frame_worst_case_bits(frame.length));
    }
    return status;
  }
  hal::Status receive(hal::CanFrame& out) override { return bus_.receive(out); }
  hal::CanBusStatus status() const override { return bus_.status(); }

 private:
  hal::CanBus& bus_;
  WireCount& count_;
};

/// A rig of `drives` CSP drives (the pan-tilt's joints' settings) in one socketcan group on a
/// classic 1 Mbit/s bus, at a rate that bus carries within the loader's limit; the master's
/// cost per cycle does not depend on the rate.
config::RigConfig bench_rig(int drives) {
  const double rate_hz = drives <= 2 ? 1000.0 : drives <= 5 ? 250.0 : 100.0;
  std::string yaml = "rig:\n  name: can_bench_" + std::to_string(drives) + "\njoints:\n";
  std::string names;
  for (int k = 1; k <= drives; ++k) {
    const std::string name = "j" + std::to_string(k);
    names += (k > 1 ? ", " : "") + name;
    yaml += "  " + name + ":\n    group: bench\n    parent: " +
            (k == 1 ? std::string("base") : "j" + std::to_string(k - 1)) +
            "\n    origin_xyz_m: [0.0, 0.0, 0.05]\n    axis: [0, 0, 1]\n"
            "    min_position_deg: -170\n    max_position_deg: 170\n"
            "    max_velocity_rad_s: 3.0\n    max_acceleration_rad_s2: 30.0\n"
            "    max_effort_nm: 2.0\n"
            "    servo: {command: position, dead_time_s: 0.002, motion_noise_std_rad: 0.0002, "
            "encoder_counts_per_rev: 65536}\n"
            "    can: {node_id: " +
            std::to_string(k) + ", gear_ratio: 50, encoder_counts_per_rev: 4096}\n";
  }
  yaml += "groups:\n  bench: {backend: socketcan, joints: [" + names +
          "], can_bus: can0, rate_hz: " + std::to_string(rate_hz) +
          "}\ncan_buses:\n  can0: {interface: can0, bitrate_bit_s: 1000000}\n";
  return config::load_rig_from_string(yaml,
                                      "can-bench rig of " + std::to_string(drives) + " drives");
}

/// The master (socketcan backend) and the virtual rig's drives on one in-process network, a
/// manual clock, stepped by the caller: configured, activated and enabled on construction.
class MasterAndDrives {
 public:
  explicit MasterAndDrives(const config::RigConfig& rig) : rig_(rig) {
    const hal::HardwareInfo hardware = config::hardware_description(rig_);
    group_name_ = rig_.groups.front().name;
    drives_ =
        std::make_unique<virtual_rig::VirtualRig>(rig_, [this](const canopen::CanBusInfo& info) {
          return std::make_unique<CountingBus>(network_.add_endpoint("rig " + info.name), wire_);
        });
    canopen::SocketCanBackendOptions options;
    options.default_joint_rate_hz = rig_.groups.front().rate_hz;
    options.waiter = [this](hal::CanBus&, std::int64_t) { let_drives_answer(); };
    backend_ = std::make_unique<canopen::SocketCanBackend>(
        hardware, canopen::can_rig_from_config(rig_), hal::BackendContext{&clock_},
        [this](const canopen::CanBusInfo& info) {
          return std::make_unique<CountingBus>(network_.add_endpoint("master " + info.name), wire_);
        },
        options);
    group_ = backend_->make_joint_group(group_name_);
    period_ns_ = std::llround(1e9 / rig_.groups.front().rate_hz);
    const std::size_t joints = group_->info().joints.size();
    states_.resize(joints);
    commands_.resize(joints);
    drives_->power_on(clock_.now_ns());
    backend_->configure();
    let_drives_answer();
    backend_->activate();
    next_cycle_ns_ = (clock_.now_ns() / period_ns_ + 1) * period_ns_;
    (void)cycle();
    for (std::size_t k = 0; k < joints; ++k) start_rad_.push_back(states_[k].position_rad);
    (void)group_->request(hal::DriveRequest::kEnable);
    for (int k = 0; k < 20 && !all_enabled(); ++k) (void)cycle();
    if (!all_enabled()) {
      throw std::runtime_error("can-bench: the emulated drives of " + rig_.name +
                               " did not reach operation enabled");
    }
  }

  /// One cycle at the next period boundary, small sines around where the joints started;
  /// returns the wall time of read + write + sync in microseconds. The drives answer after it.
  double cycle() {
    clock_.advance_to_ns(next_cycle_ns_);
    const double t_s = static_cast<double>(next_cycle_ns_) * 1e-9;
    next_cycle_ns_ += period_ns_;
    for (std::size_t k = 0; k < commands_.size(); ++k) {
      const double base_rad = k < start_rad_.size() ? start_rad_[k] : 0.0;
      commands_[k] = {hal::CommandMode::kPosition,
                      base_rad + 0.1 * std::sin(2.0 * t_s + static_cast<double>(k)), 0.0, 0.0};
    }
    std::int64_t stamp_ns = 0;
    const auto start = WallClock::now();
    const hal::Status read = group_->read(states_, stamp_ns);
    (void)group_->write(commands_);
    const hal::Status sync = group_->sync();
    const double elapsed_us =
        std::chrono::duration<double, std::micro>(WallClock::now() - start).count();
    if (sync != hal::Status::kOk || read == hal::Status::kFault) {
      throw std::runtime_error("can-bench: the master's cycle failed on " + rig_.name);
    }
    let_drives_answer();
    return elapsed_us;
  }

  const WireCount& wire() const { return wire_; }
  std::int64_t period_ns() const { return period_ns_; }
  const canopen::CanJointGroup& group() const { return *backend_->group(group_name_); }

 private:
  void let_drives_answer() {
    clock_.advance_to_ns(clock_.now_ns() + kAnswerDelayNs);
    for (std::size_t b = 0; b < drives_->bus_count(); ++b)
      (void)drives_->process(b, clock_.now_ns());
  }
  bool all_enabled() const {
    return std::all_of(states_.begin(), states_.end(), [](const hal::JointState& s) {
      return s.drive_state == hal::DriveState::kOperationEnabled;
    });
  }

  config::RigConfig rig_;
  hal::ManualClock clock_{1'000'000'000};
  can::InProcessCanNetwork network_{false, &clock_};
  WireCount wire_;
  std::string group_name_;
  std::unique_ptr<virtual_rig::VirtualRig> drives_;
  std::unique_ptr<canopen::SocketCanBackend> backend_;
  std::unique_ptr<hal::JointGroup> group_;
  std::int64_t period_ns_ = 1'000'000;
  std::int64_t next_cycle_ns_ = 0;
  std::vector<hal::JointState> states_;
  std::vector<hal::JointCommand> commands_;
  std::vector<double> start_rad_;
};

/// Where the PDO loop's result goes: the optimiser must assume someone reads it, so the loop is
/// not dead code.
volatile std::uint64_t pdo_checksum_sink = 0;

/// Packs and unpacks RPDO1 and TPDO1 of a CSP drive `frame_pairs` times; returns frames (one
/// pack plus one unpack each) per second.
double pdo_frames_per_s(long long frame_pairs) {
  const canopen::PdoLayout layout = canopen::pdo_layout(hal::CommandMode::kPosition, {});
  hal::CanFrame frame;
  canopen::DriveTargets targets;
  canopen::DriveFeedback feedback;
  std::uint64_t checksum = 0;
  const auto start = WallClock::now();
  for (long long i = 0; i < frame_pairs; ++i) {
    targets.controlword = static_cast<std::uint16_t>(0x000F ^ (i & 1));
    targets.target_position_counts = static_cast<std::int32_t>(i * 7);
    canopen::pack_pdo(
        layout.rpdos[0], 0x201,
        [&targets](canopen::ObjectAddress object) { return canopen::raw_target(targets, object); },
        frame);
    canopen::DriveTargets received;
    (void)canopen::unpack_pdo(
        layout.rpdos[0], frame,
        [&received](canopen::ObjectAddress object, std::uint32_t raw, std::size_t) {
          if (object == canopen::cia402::kControlword) {
            received.controlword = static_cast<std::uint16_t>(raw);
          } else {
            received.target_position_counts = static_cast<std::int32_t>(raw);
          }
        });
    feedback.statusword = received.controlword;
    feedback.position_counts = received.target_position_counts - 3;
    canopen::pack_pdo(
        layout.tpdos[0], 0x181,
        [&feedback](canopen::ObjectAddress object) -> std::uint32_t {
          if (object == canopen::cia402::kStatusword) return feedback.statusword;
          return static_cast<std::uint32_t>(feedback.position_counts);
        },
        frame);
    canopen::DriveFeedback decoded;
    (void)canopen::unpack_pdo(
        layout.tpdos[0], frame,
        [&decoded](canopen::ObjectAddress object, std::uint32_t raw, std::size_t bytes) {
          canopen::store_feedback(decoded, object, raw, bytes);
        });
    checksum += static_cast<std::uint32_t>(decoded.position_counts) + decoded.statusword;
  }
  const double elapsed_s = std::chrono::duration<double>(WallClock::now() - start).count();
  pdo_checksum_sink = checksum;
  return 2.0 * static_cast<double>(frame_pairs) / elapsed_s;
}

}  // namespace

int run_can_bench_command(std::span<const std::string> args) {
  ArgumentParser parser("can-bench",
                        "measure the CANopen master's cost and the bus load on the in-process bus");
  parser.option("cycles", "N", "joint-loop cycles per round and per case (default 2000)")
      .option("rounds", "R", "alternating rounds; the figures are their medians (default 10)")
      .flag("json", "print one JSON object instead of a table");
  if (!parser.parse(args)) return kExitOk;
  const auto cycles = static_cast<int>(
      parser.integer("cycles", 2000, config::Range::closed(100, 1'000'000),
                     "a p99 needs at least 100 cycles; a million is minutes of run time"));
  const auto rounds = static_cast<int>(parser.integer("rounds", 10, config::Range::closed(10, 1000),
                                                      "the figures are medians over >= 10 rounds"));

  // The master's cycle, 2, 5 and 10 drives, one round of each in turn.
  const std::vector<int> drive_counts = {2, 5, 10};
  std::vector<std::unique_ptr<MasterAndDrives>> rigs;
  for (const int drives : drive_counts) {
    rigs.push_back(std::make_unique<MasterAndDrives>(bench_rig(drives)));
  }
  std::vector<std::vector<double>> p50_us(drive_counts.size()), p99_us(drive_counts.size());
  std::vector<double> pdo_rates;
  std::vector<double> samples(static_cast<std::size_t>(cycles));
  const long long frame_pairs = 200LL * cycles;
  (void)pdo_frames_per_s(frame_pairs / 10);  // Warm-up.
  for (int round = 0; round < rounds; ++round) {
    for (std::size_t r = 0; r < rigs.size(); ++r) {
      for (int i = 0; i < cycles; ++i) samples[static_cast<std::size_t>(i)] = rigs[r]->cycle();
      p50_us[r].push_back(percentile(samples, 0.50));
      p99_us[r].push_back(percentile(samples, 0.99));
    }
    pdo_rates.push_back(pdo_frames_per_s(frame_pairs));
  }

  // Bus load: the shipped pan-tilt on socketcan at its 1 kHz, every frame on the bus counted
  // (RPDOs, SYNC, TPDOs, heartbeats, anything else) over `cycles` cycles of simulated time.
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
  const double measured_load = static_cast<double>(after.bits - before.bits) / window_s /
                               static_cast<double>(bus.bitrate_bit_s);
  const double model_load =
      canopen::can_bus_load(config::hardware_description(pan_tilt), pan_tilt_can, bus,
                            canopen::SocketCanBackend::kName)
          .load;
  const auto counters = pan_tilt_bus.group().counters();

  const long rss_kib = peak_rss_kib();
  const double pdo_rate = median(pdo_rates);
  if (parser.flag_set("json")) {
    Json cycle_us = Json::object();
    for (std::size_t r = 0; r < drive_counts.size(); ++r) {
      cycle_us[std::to_string(drive_counts[r])] = {{"p50", as_printed(median(p50_us[r]), "%.3g")},
                                                   {"p99", as_printed(median(p99_us[r]), "%.3g")}};
    }
    const Json figures = {
        {"bus", "in-process (host)"},
        {"emulated", false},
        {"rounds", rounds},
        {"cycles_per_round", cycles},
        {"pdo_frames_per_s_per_core", as_printed(pdo_rate, "%.3g")},
        {"master_cycle_us", cycle_us},
        {"bus_load_rig", pan_tilt.name},
        {"bus_load_bus", bus.name},
        {"bus_load_rate_hz", pan_tilt.groups.front().rate_hz},
        {"bus_load_frames", after.frames - before.frames},
        {"bus_load_measured", as_printed(measured_load, "%.4f")},
        {"bus_load_model", as_printed(model_load, "%.4f")},
        {"bus_load_missed_sync_answers", counters.missed_sync_answers},
        {"peak_rss_kib", rss_kib},
    };
    std::cout << json_text(figures);
    return kExitOk;
  }
  std::printf("cambio can-bench: in-process bus (host), medians of %d alternating rounds\n",
              rounds);
  std::printf("  PDO frames packed+unpacked  %12.3g /s per core\n", pdo_rate);
  for (std::size_t r = 0; r < drive_counts.size(); ++r) {
    std::printf("  master cycle, %2d drives     p50 %8.2f us   p99 %8.2f us\n", drive_counts[r],
                median(p50_us[r]), median(p99_us[r]));
  }
  std::printf("  bus load, %s %s at %g Hz: measured %.2f %%, model %.2f %% (%d cycles)\n",
              pan_tilt.name.c_str(), bus.name.c_str(), pan_tilt.groups.front().rate_hz,
              100.0 * measured_load, 100.0 * model_load, cycles);
  std::printf("  peak RSS                    %12ld KiB\n", rss_kib);
  return kExitOk;
}

}  // namespace cambio::app
