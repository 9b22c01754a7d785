#include "can_bench_rig.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <stdexcept>

#include "cambio/canopen/can_bus_load.hpp"
#include "cambio/canopen/can_rig_from_config.hpp"
#include "cambio/config/hardware_description.hpp"
#include "cambio/config/rig_loader.hpp"

namespace cambio::app {

namespace {

using WallClock = std::chrono::steady_clock;

/// When the emulated drives handle what the master sent, after it went out.
constexpr std::int64_t kAnswerDelayNs = 100'000;

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

}  // namespace

config::RigConfig can_bench_rig(int drives) {
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

MasterAndDrives::MasterAndDrives(const config::RigConfig& rig) : rig_(rig) {
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

double MasterAndDrives::cycle() {
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

void MasterAndDrives::let_drives_answer() {
  clock_.advance_to_ns(clock_.now_ns() + kAnswerDelayNs);
  for (std::size_t b = 0; b < drives_->bus_count(); ++b) (void)drives_->process(b, clock_.now_ns());
}

bool MasterAndDrives::all_enabled() const {
  return std::all_of(states_.begin(), states_.end(), [](const hal::JointState& s) {
    return s.drive_state == hal::DriveState::kOperationEnabled;
  });
}

}  // namespace cambio::app
