#pragma once

// The real CANopen master (the socketcan backend and its CanJointGroup) and the real virtual rig
// (emulated CiA 402 drives on the sim's servo model) for the shipped pan-tilt rig with its group
// switched to socketcan, on one in-process bus with a manual clock, stepped in one thread.

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <functional>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "cambio/can/in_process_can_bus.hpp"
#include "cambio/canopen/can_rig_from_config.hpp"
#include "cambio/canopen/socketcan_backend.hpp"
#include "cambio/config/hardware_description.hpp"
#include "cambio/config/rig_loader.hpp"
#include "cambio/hal/manual_clock.hpp"
#include "cambio/runtime/allocation_counter.hpp"
#include "cambio/virtual_rig/virtual_rig.hpp"

namespace cambio::virtual_rig::test {

/// Hands an endpoint of the test's network to the rig or the master; on the master's side it
/// records the master's traffic in order, both ways.
class EndpointRef final : public hal::CanBus {
 public:
  struct Sent {
    hal::CanFrame frame;
    bool received = false;  ///< Taken by the master, not sent by it.
  };
  explicit EndpointRef(hal::CanBus& bus, std::vector<Sent>* sent = nullptr)
      : bus_(bus), sent_(sent) {}
  const std::string& name() const override { return bus_.name(); }
  hal::Status send(const hal::CanFrame& frame) override {
    const hal::Status status = bus_.send(frame);
    if (sent_ != nullptr && status == hal::Status::kOk) sent_->push_back({frame, false});
    return status;
  }
  hal::Status receive(hal::CanFrame& out) override {
    const hal::Status status = bus_.receive(out);
    if (sent_ != nullptr && status == hal::Status::kOk) sent_->push_back({out, true});
    return status;
  }
  hal::CanBusStatus status() const override { return bus_.status(); }

 private:
  hal::CanBus& bus_;
  std::vector<Sent>* sent_;
};

constexpr std::int64_t kStartNs = 1'000'000'000;
/// When the drives handle what the master sent, after it went out (well inside a cycle).
constexpr std::int64_t kAnswerDelayNs = 100'000;

/// The pan-tilt rig on socketcan: master and virtual rig on one in-process network.
struct MasterAndRig {
  /// `overrides` go on top of the rig file as `--set` does (the group's backend is socketcan).
  explicit MasterAndRig(std::vector<config::ConfigOverride> overrides = {}) {
    overrides.insert(overrides.begin(), {"groups.pan_tilt.backend", "socketcan"});
    rig = config::load_rig(std::string(CAMBIO_SOURCE_DIR) + "/firmware_config/rigs/pan_tilt.yaml",
                           overrides);
    hardware = config::hardware_description(rig);
    drives = std::make_unique<VirtualRig>(rig, [this](const canopen::CanBusInfo& info) {
      return std::make_unique<EndpointRef>(network.add_endpoint("rig " + info.name));
    });
    canopen::SocketCanBackendOptions options;
    options.default_joint_rate_hz = rig.groups[0].rate_hz;
    // While configure() waits for an answer, time passes and the drives answer.
    options.waiter = [this](hal::CanBus&, std::int64_t) { let_drives_answer(); };
    hal::BackendContext context;
    context.clock = &clock;
    backend = std::make_unique<canopen::SocketCanBackend>(
        hardware, canopen::can_rig_from_config(rig), context,
        [this](const canopen::CanBusInfo& info) {
          return std::make_unique<EndpointRef>(network.add_endpoint("master " + info.name), &sent);
        },
        options);
    group = backend->make_joint_group("pan_tilt");
    period_ns = std::llround(1e9 / rig.groups[0].rate_hz);
    drives->power_on(clock.now_ns());
  }

  void let_drives_answer() {
    clock.advance_to_ns(clock.now_ns() + kAnswerDelayNs);
    (void)drives->process(0, clock.now_ns());
    if (on_answer) on_answer();
  }

  /// Configures and activates, and starts the cycle clock on a period boundary.
  void start() {
    backend->configure();
    let_drives_answer();  // The drives take the NMT start.
    backend->activate();
    next_cycle_ns = (clock.now_ns() / period_ns + 1) * period_ns;
  }

  /// One joint-loop cycle at the next period boundary: read, write `commands` (none: hold), SYNC;
  /// then the drives answer. Returns read()'s status.
  hal::Status cycle(const std::vector<hal::JointCommand>* commands = nullptr) {
    clock.advance_to_ns(next_cycle_ns);
    next_cycle_ns += period_ns;
    const std::uint64_t allocations_before = runtime::thread_allocation_count();
    const hal::Status status = group->read(states, stamp_ns);
    sent_at_read = sent.size();
    const hal::Status written = commands != nullptr ? group->write(*commands) : hal::Status::kOk;
    const hal::Status synced = group->sync();
    group_allocations += runtime::thread_allocation_count() - allocations_before;
    EXPECT_EQ(written, hal::Status::kOk);
    EXPECT_EQ(synced, hal::Status::kOk);
    let_drives_answer();
    return status;
  }

  /// Holds every joint where it is measured now.
  std::vector<hal::JointCommand> hold_here() const {
    std::vector<hal::JointCommand> commands;
    for (const auto& state : states) {
      commands.push_back({hal::CommandMode::kPosition, state.position_rad, 0.0, 0.0});
    }
    return commands;
  }

  /// Cycles (holding `commands`) until every joint is operation enabled; returns the cycles.
  int enable(const std::vector<hal::JointCommand>& commands) {
    EXPECT_EQ(group->request(hal::DriveRequest::kEnable), hal::Status::kOk);
    for (int k = 1; k <= 20; ++k) {
      (void)cycle(&commands);
      if (std::all_of(states.begin(), states.end(), [](const hal::JointState& s) {
            return s.drive_state == hal::DriveState::kOperationEnabled;
          })) {
        return k;
      }
    }
    return -1;
  }

  EmulatedDrive& drive(std::size_t k) { return drives->drive(0, k); }
  double seconds_since_power_on() const {
    return static_cast<double>(clock.now_ns() - kStartNs) * 1e-9;
  }

  hal::ManualClock clock{kStartNs};
  can::InProcessCanNetwork network{false, &clock};
  config::RigConfig rig;
  hal::HardwareInfo hardware;
  std::unique_ptr<VirtualRig> drives;
  std::vector<EndpointRef::Sent> sent;
  std::unique_ptr<canopen::SocketCanBackend> backend;
  std::unique_ptr<hal::JointGroup> group;
  std::int64_t period_ns = 1'000'000;
  std::int64_t next_cycle_ns = 0;
  std::vector<hal::JointState> states = std::vector<hal::JointState>(2);
  std::int64_t stamp_ns = 0;
  std::size_t sent_at_read = 0;  ///< Frames in `sent` when the last read() returned.
  /// What the group's read/write/sync allocated, over every cycle() (reserve `sent` first: the
  /// recording of the master's frames grows it inside sync()).
  std::uint64_t group_allocations = 0;
  /// Called each time the drives answered (a test's event: a drive that reboots, say).
  std::function<void()> on_answer;
};

}  // namespace cambio::virtual_rig::test
