// The CAN joint group's cycle against the test's own CiA 402 drive (test_drive.hpp) on the
// in-process bus, time driven by a ManualClock: controlword sequences (CiA 402-2 Table 29),
// enabling at the measured position, heartbeat loss, EMCY, stale readings, no motion after a
// fault, bad frames, a rebooted drive configured again from the loop, effort in N m against the
// closed form, bus-off and its recovery, and no allocation in read/write/sync.
#include "cambio/canopen/can_joint_group.hpp"
#include "cambio/canopen/can_bus_load.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <limits>
#include <memory>
#include <vector>

#include "cambio/can/in_process_can_bus.hpp"
#include "cambio/canopen/pdo_configuration.hpp"
#include "cambio/hal/manual_clock.hpp"
#include "cambio/runtime/allocation_counter.hpp"
#include "test_drive.hpp"

namespace cambio::canopen {
namespace {

using hal::DriveRequest;
using hal::DriveState;

constexpr std::int64_t kPeriodNs = 1'000'000;  // 1 kHz.
constexpr std::int32_t kStartCounts = 12345;

/// An in-process endpoint whose controller can be switched bus-off: sends fail with kFault,
/// nothing is received (frames on the wire meanwhile are lost to it), status() says kBusOff.
class SwitchableBus final : public hal::CanBus {
 public:
  explicit SwitchableBus(hal::CanBus& bus) : bus_(bus) {}
  const std::string& name() const override { return bus_.name(); }
  hal::Status send(const hal::CanFrame& frame) override {
    return off ? hal::Status::kFault : bus_.send(frame);
  }
  hal::Status receive(hal::CanFrame& out) override {
    if (!off) return bus_.receive(out);
    while (bus_.receive(out) == hal::Status::kOk) {
    }
    return hal::Status::kNoNewData;
  }
  hal::CanBusStatus status() const override {
    hal::CanBusStatus status = bus_.status();
    if (off) status.state = hal::CanBusState::kBusOff;
    return status;
  }
  bool off = false;

 private:
  hal::CanBus& bus_;
};

struct Fixture {
  explicit Fixture(int joints = 1, canopen::CanGroupSettings settings = {}) {
    hal::JointGroupInfo info;
    info.name = "head";
    info.backend = "socketcan";
    std::vector<canopen::JointDriveInfo> drive_infos;
    for (int k = 0; k < joints; ++k) {
      info.joints.push_back("j" + std::to_string(k));
      info.limits.push_back({-1.0, 1.0, 2.0, 10.0, 0.0});
      canopen::JointDriveInfo drive;
      drive.node_id = 10 + k;
      drive.gear_ratio = 10.0;
      drive.encoder_counts_per_rev = 10000;
      drive_infos.push_back(drive);
      drives.push_back(std::make_unique<testing::TestDrive>(
          network.add_endpoint("drive" + std::to_string(k)), drive.node_id));
    }
    group = std::make_unique<CanJointGroup>(info, settings, drive_infos, 1000.0, bus, clock);
    BusPump pump(master, clock, [this](hal::CanBus&, std::int64_t) { step_drives(); });
    for (int k = 0; k < joints; ++k) {
      const int node = 10 + k;
      const std::vector<ObjectWrite> writes = pdo_configuration_writes(node, group->layout());
      write_objects(pump, node, writes, 0.1);
      group->set_configuration(static_cast<std::size_t>(k), writes);
      group->set_rated_torque(static_cast<std::size_t>(k), 2.0);
      drives[static_cast<std::size_t>(k)]->nmt_state = 0x05;
      drives[static_cast<std::size_t>(k)]->position_counts = kStartCounts;
      DriveFeedback seed;
      seed.statusword = 0x0040;
      seed.position_counts = kStartCounts;
      group->seed_feedback(static_cast<std::size_t>(k), seed, clock.now_ns());
    }
    states.resize(static_cast<std::size_t>(joints));
    commands.resize(static_cast<std::size_t>(joints), {hal::CommandMode::kPosition, 0.5, 0, 0});
    group->arm(clock.now_ns());
  }

  void step_drives() {
    for (auto& drive : drives) drive->step();
  }

  /// One joint-loop cycle, then the drives answer the SYNC.
  hal::Status cycle() {
    clock.advance_to_ns(clock.now_ns() + kPeriodNs);
    std::int64_t stamp_ns = 0;
    hal::Status status = group->read(states, stamp_ns);
    status = hal::worst(status, group->write(commands));
    status = hal::worst(status, group->sync());
    step_drives();
    return status;
  }

  hal::ManualClock clock{1'000'000'000};
  can::InProcessCanNetwork network{false, &clock};
  hal::CanBus& master = network.add_endpoint("master");
  SwitchableBus bus{master};
  std::vector<std::unique_ptr<testing::TestDrive>> drives;
  std::unique_ptr<CanJointGroup> group;
  std::vector<hal::JointState> states;
  std::vector<hal::JointCommand> commands;
};

// The group's count of its bus's traffic (one group per bus) against a listener on the same bus:
// every frame the group sent and every drive's answer, their worst-case bits summed as
// can_frame_worst_case_bits says (SYNC 55 bits, 8 data bytes 135).
TEST(CanJointGroup, CountsEveryFrameOnItsBusAndItsBitsAsAListenerSeesThem) {
  Fixture f(2);
  hal::CanBus& listener = f.network.add_endpoint("listener", 1 << 16);
  const canopen::CanGroupCounters before = f.group->counters();
  ASSERT_EQ(f.group->request(DriveRequest::kEnable), hal::Status::kOk);
  for (int k = 0; k < 200; ++k) {
    if (k % 50 == 0) {
      for (auto& drive : f.drives) drive->send_heartbeat();
    }
    (void)f.cycle();
  }
  std::int64_t stamp_ns = 0;
  (void)f.group->read(f.states, stamp_ns);  // The drives' last answers.
  std::uint64_t frames = 0;
  std::uint64_t bits = 0;
  hal::CanFrame frame;
  while (listener.receive(frame) == hal::Status::kOk) {
    ++frames;
    bits += static_cast<std::uint64_t>(canopen::can_frame_worst_case_bits(frame.length));
  }
  const canopen::CanGroupCounters after = f.group->counters();
  EXPECT_EQ(after.frames_sent - before.frames_sent + after.frames_received - before.frames_received,
            frames);
  EXPECT_EQ(after.bus_bits - before.bus_bits, bits);
  // Two drives: at least RPDO1 each and a SYNC per cycle, and each drive's TPDO1 answer.
  EXPECT_GE(after.frames_sent - before.frames_sent, 3u * 200u);
  EXPECT_GE(after.frames_received - before.frames_received, 2u * 199u);
}

TEST(CanJointGroup, EnableWalksCia402AndStartsAtTheMeasuredPosition) {
  Fixture f;
  ASSERT_EQ(f.group->request(DriveRequest::kEnable), hal::Status::kOk);
  for (int k = 0; k < 6; ++k) (void)f.cycle();
  const auto& drive = *f.drives[0];
  // Shutdown, switch on, enable operation (Table 29), then enable operation held.
  ASSERT_GE(drive.controlwords_at_sync.size(), 6u);
  EXPECT_EQ(drive.controlwords_at_sync[0], 0x0006);
  EXPECT_EQ(drive.controlwords_at_sync[1], 0x0007);
  EXPECT_EQ(drive.controlwords_at_sync[2], 0x000F);
  EXPECT_EQ(drive.controlwords_at_sync[3], 0x000F);
  // Until the master has seen the drive enabled for a whole cycle, the target is where the
  // drive is: enabling never jumps.
  for (std::size_t i = 0; i < 4; ++i) EXPECT_EQ(drive.targets_at_sync[i], kStartCounts) << i;
  const auto units = cia402::Units::from(10.0, 10000);
  EXPECT_EQ(drive.targets_at_sync[4], units.to_counts(0.5));
  std::int64_t stamp_ns = 0;
  ASSERT_EQ(f.group->read(f.states, stamp_ns), hal::Status::kOk);
  EXPECT_EQ(f.states[0].drive_state, DriveState::kOperationEnabled);
  EXPECT_NEAR(f.states[0].position_rad, 0.5, 1.0 / units.counts_per_rad);
  EXPECT_EQ(f.states[0].status_bits, hal::kJointOk);
  EXPECT_EQ(f.states[0].stamp_ns, f.clock.now_ns()) << "stamped by its TPDO's arrival";
}

TEST(CanJointGroup, DisableQuickStopAndReEnable) {
  Fixture f;
  (void)f.group->request(DriveRequest::kEnable);
  for (int k = 0; k < 5; ++k) (void)f.cycle();
  ASSERT_EQ(f.drives[0]->state, DriveState::kOperationEnabled);
  (void)f.group->request(DriveRequest::kQuickStop);
  (void)f.cycle();
  EXPECT_EQ(f.drives[0]->controlwords_at_sync.back(), 0x0002);
  EXPECT_EQ(f.drives[0]->state, DriveState::kQuickStopActive);
  (void)f.group->request(DriveRequest::kEnable);
  (void)f.cycle();
  (void)f.cycle();
  EXPECT_EQ(f.drives[0]->state, DriveState::kOperationEnabled) << "transition 16";
  (void)f.group->request(DriveRequest::kDisable);
  (void)f.cycle();
  EXPECT_EQ(f.drives[0]->controlwords_at_sync.back(), 0x0000);
  EXPECT_EQ(f.drives[0]->state, DriveState::kSwitchOnDisabled);
}

TEST(CanJointGroup, FaultHoldsTheWholeGroupUntilResetThenReEnablesWithoutJump) {
  Fixture f(2);
  (void)f.group->request(DriveRequest::kEnable);
  for (int k = 0; k < 6; ++k) (void)f.cycle();
  ASSERT_EQ(f.drives[1]->state, DriveState::kOperationEnabled);
  f.drives[0]->fault();
  f.commands = {{hal::CommandMode::kPosition, -0.5, 0, 0},
                {hal::CommandMode::kPosition, -0.5, 0, 0}};
  (void)f.cycle();  // The drive reports its fault.
  EXPECT_EQ(f.cycle(), hal::Status::kFault);
  EXPECT_NE(f.states[0].status_bits & hal::kJointFault, 0u);
  const std::int32_t held = f.drives[1]->position_counts;
  for (int k = 0; k < 5; ++k) (void)f.cycle();
  // No motion command went out: the healthy drive was quick-stopped where it was.
  EXPECT_EQ(f.drives[1]->controlwords_at_sync.back(), 0x0002);
  EXPECT_EQ(f.drives[1]->state, DriveState::kQuickStopActive);
  EXPECT_EQ(f.drives[1]->position_counts, held);
  EXPECT_EQ(f.drives[1]->targets_at_sync.back(), held);
  EXPECT_EQ(f.drives[0]->controlwords_at_sync.back(), 0x0000) << "a faulted drive waits";

  (void)f.group->request(DriveRequest::kFaultReset);
  for (int k = 0; k < 3; ++k) (void)f.cycle();
  // Bit 7 rises once after a low controlword (the drive acts on the edge).
  const auto& words = f.drives[0]->controlwords_at_sync;
  EXPECT_EQ(words[words.size() - 3], 0x0080);
  EXPECT_EQ(f.drives[0]->state, DriveState::kSwitchOnDisabled);
  EXPECT_EQ(f.cycle(), hal::Status::kOk);
  EXPECT_EQ(f.states[0].status_bits & hal::kJointLatchingBits, 0u);

  (void)f.group->request(DriveRequest::kEnable);
  const std::int32_t at_reenable = f.drives[1]->position_counts;
  for (int k = 0; k < 4; ++k) (void)f.cycle();
  EXPECT_EQ(f.drives[1]->state, DriveState::kOperationEnabled);
  EXPECT_EQ(f.drives[1]->targets_at_sync.back(), at_reenable) << "first target: where it is";
  (void)f.cycle();
  const auto units = cia402::Units::from(10.0, 10000);
  EXPECT_EQ(f.drives[1]->targets_at_sync.back(), units.to_counts(-0.5));
}

TEST(CanJointGroup, HeartbeatLossLatchesWithinThreePeriods) {
  canopen::CanGroupSettings settings;
  settings.heartbeat_period_s = 0.1;
  Fixture f(1, settings);
  std::int64_t lost_at_ns = 0;
  std::int64_t last_heartbeat_ns = 0;
  for (int k = 1; k <= 2000 && lost_at_ns == 0; ++k) {
    // Heartbeats every 100 ms until t0 + 1 s, then silence.
    if (k % 100 == 0 && k <= 1000) {
      f.drives[0]->send_heartbeat();
      last_heartbeat_ns = f.clock.now_ns();
    }
    (void)f.cycle();
    if ((f.states[0].status_bits & hal::kJointCommLost) != 0) lost_at_ns = f.clock.now_ns();
  }
  ASSERT_GT(lost_at_ns, 0);
  EXPECT_GT(lost_at_ns - last_heartbeat_ns, 300'000'000);
  EXPECT_LE(lost_at_ns - last_heartbeat_ns, 300'000'000 + kPeriodNs);
  // Latched: heartbeats again do not clear it; a fault reset does.
  f.drives[0]->send_heartbeat();
  EXPECT_EQ(f.cycle(), hal::Status::kFault);
  EXPECT_NE(f.states[0].status_bits & hal::kJointCommLost, 0u);
  (void)f.group->request(DriveRequest::kFaultReset);
  f.drives[0]->send_heartbeat();
  (void)f.cycle();
  EXPECT_EQ(f.states[0].status_bits & hal::kJointCommLost, 0u);
}

/// Cycles until `done()` or `max_cycles`; returns the cycles run.
template <class Done>
int cycle_until(Fixture& f, Done&& done, int max_cycles = 200) {
  int k = 0;
  while (k < max_cycles && !done()) {
    (void)f.cycle();
    ++k;
  }
  return k;
}

TEST(CanJointGroup, ARebootedDriveIsReconfiguredOnResetAndEnabledOnlyOnRequest) {
  Fixture f(2);
  hal::CanBus& probe = f.network.add_endpoint("probe");
  (void)f.group->request(DriveRequest::kEnable);
  for (int k = 0; k < 8; ++k) (void)f.cycle();
  ASSERT_EQ(f.drives[0]->state, DriveState::kOperationEnabled);
  const std::vector<testing::TestDrive::Write> first_configuration = [&] {
    std::vector<testing::TestDrive::Write> writes;
    for (const ObjectWrite& w : pdo_configuration_writes(10, f.group->layout())) {
      writes.push_back({w.object.index, w.object.subindex, w.value, w.bytes});
    }
    return writes;
  }();

  f.drives[0]->reboot();
  f.drives[0]->position_counts = 20000;  // It was pushed while unpowered.
  EXPECT_EQ(f.cycle(), hal::Status::kFault);
  EXPECT_NE(f.states[0].status_bits & hal::kJointCommLost, 0u);
  EXPECT_TRUE(f.group->needs_reconfiguration(0));
  for (int k = 0; k < 20; ++k) (void)f.cycle();
  EXPECT_TRUE(f.drives[0]->writes.empty()) << "nothing is replayed before a fault reset";
  EXPECT_EQ(f.drives[1]->state, DriveState::kQuickStopActive) << "the group holds";

  (void)f.group->request(DriveRequest::kFaultReset);
  hal::CanFrame frame;
  while (probe.receive(frame) == hal::Status::kOk) {
  }
  int most_requests_per_cycle = 0;
  const int cycles = cycle_until(f, [&] {
    int requests = 0;
    while (probe.receive(frame) == hal::Status::kOk) requests += frame.id == 0x60A ? 1 : 0;
    most_requests_per_cycle = std::max(most_requests_per_cycle, requests);
    return f.group->counters().reconfigurations > 0;
  });
  ASSERT_EQ(f.group->counters().reconfigurations, 1u) << "after " << cycles << " cycles";
  EXPECT_EQ(most_requests_per_cycle, 1) << "one SDO exchange in flight at a time";
  ASSERT_EQ(f.drives[0]->writes.size(), first_configuration.size());
  for (std::size_t i = 0; i < first_configuration.size(); ++i) {
    EXPECT_EQ(f.drives[0]->writes[i].index, first_configuration[i].index) << i;
    EXPECT_EQ(f.drives[0]->writes[i].subindex, first_configuration[i].subindex) << i;
    EXPECT_EQ(f.drives[0]->writes[i].value, first_configuration[i].value) << i;
  }
  EXPECT_EQ(f.drives[0]->nmt_state, 0x05) << "started again";
  EXPECT_FALSE(f.group->needs_reconfiguration(0));
  EXPECT_EQ(f.group->counters().reconfiguration_failures, 0u);

  (void)f.cycle();
  (void)f.cycle();
  EXPECT_EQ(f.states[0].status_bits & hal::kJointLatchingBits, 0u);
  EXPECT_NE(f.states[0].status_bits & hal::kJointNotEnabled, 0u) << "not re-enabled by itself";
  EXPECT_EQ(f.drives[0]->state, DriveState::kSwitchOnDisabled);
  const auto units = cia402::Units::from(10.0, 10000);
  EXPECT_EQ(f.states[0].position_rad, units.to_rad(20000));

  (void)f.group->request(DriveRequest::kEnable);
  cycle_until(f, [&] { return f.drives[0]->state == DriveState::kOperationEnabled; });
  ASSERT_EQ(f.drives[0]->state, DriveState::kOperationEnabled);
  EXPECT_EQ(f.drives[0]->targets_at_sync.back(), 20000) << "enabled where it is: no jump";
  (void)f.cycle();
  (void)f.cycle();
  EXPECT_EQ(f.drives[0]->targets_at_sync.back(), units.to_counts(0.5)) << "then driven";
}

TEST(CanJointGroup, AReconfigurationTheDriveRefusesStaysFaultedAndSaysWhy) {
  Fixture f;
  f.drives[0]->reboot();
  f.drives[0]->clamp_on_write[testing::TestDrive::key(0x1A00, 0)] = 1;
  (void)f.cycle();
  (void)f.group->request(DriveRequest::kFaultReset);
  cycle_until(f, [&] { return f.group->counters().reconfiguration_failures > 0; });
  EXPECT_EQ(f.group->counters().reconfiguration_failures, 1u);
  EXPECT_EQ(f.group->counters().reconfigurations, 0u);
  const ReconfigurationError error = f.group->last_reconfiguration_error();
  EXPECT_EQ(error.node_id, 10);
  EXPECT_STREQ(error.text.data(), "node 10: object 0x1A00:00 written 2 (0x02), read back 1 (0x01)");
  (void)f.cycle();
  EXPECT_NE(f.states[0].status_bits & hal::kJointCommLost, 0u);
  EXPECT_EQ(f.drives[0]->nmt_state, 0x7F) << "never started";

  // A drive that stops answering: the SDO timeout (0.1 s) ends it, named.
  f.drives[0]->clamp_on_write.clear();
  f.drives[0]->answer_sdo = false;
  (void)f.group->request(DriveRequest::kFaultReset);
  cycle_until(f, [&] { return f.group->counters().reconfiguration_failures > 1; });
  EXPECT_EQ(f.group->counters().reconfiguration_failures, 2u);
  EXPECT_STREQ(f.group->last_reconfiguration_error().text.data(),
               "node 10: SDO download to 0x1400:01 not answered in time: 0x05040000 (SDO "
               "protocol timed out)");

  // Answering again, a new reset succeeds.
  f.drives[0]->answer_sdo = true;
  (void)f.group->request(DriveRequest::kFaultReset);
  cycle_until(f, [&] { return f.group->counters().reconfigurations > 0; });
  EXPECT_EQ(f.group->counters().reconfigurations, 1u);
  (void)f.cycle();
  EXPECT_EQ(f.states[0].status_bits & hal::kJointLatchingBits, 0u);
}

TEST(CanJointGroup, EffortIsPerMilleOfRatedMotorTorqueTimesGear) {
  canopen::CanGroupSettings settings;
  settings.effort_feedforward = true;
  settings.effort_feedback = true;
  Fixture f(1, settings);  // Gear 10, rated 2 N m.
  f.commands[0].effort_feedforward_nm = 3.0;
  f.drives[0]->torque_actual_per_mille = -250;
  (void)f.group->request(DriveRequest::kEnable);
  for (int k = 0; k < 8; ++k) (void)f.cycle();
  // 3 N m at the joint = 0.3 N m at the motor = 150 per mille of 2 N m.
  EXPECT_EQ(f.drives[0]->last_torque_offset, 150);
  // -250 per mille of 2 N m = -0.5 N m at the motor = -5 N m at the joint.
  EXPECT_DOUBLE_EQ(f.states[0].effort_nm, -5.0);
}

TEST(TorqueUnits, ClosedFormSignAndSaturation) {
  const TorqueUnits torque{0.8, -50.0};
  // tau_joint = tau_motor * gear: 1 per mille = 0.8 mN m at the motor = -40 mN m at the joint.
  EXPECT_DOUBLE_EQ(torque.to_joint_nm(1), -0.04);
  EXPECT_EQ(torque.to_per_mille(-0.04), 1);
  EXPECT_EQ(torque.to_per_mille(10.0), -250);
  EXPECT_EQ(torque.to_per_mille(1e9), INT16_MIN);
  EXPECT_EQ(torque.to_per_mille(std::numeric_limits<double>::quiet_NaN()), 0);
  EXPECT_EQ((TorqueUnits{0.0, 10.0}.to_per_mille(5.0)), 0) << "unknown rated torque";
}

TEST(CanJointGroup, BusOffLatchesTheGroupUntilAResetOnAWorkingBus) {
  Fixture f(2);
  (void)f.group->request(DriveRequest::kEnable);
  for (int k = 0; k < 8; ++k) (void)f.cycle();
  ASSERT_EQ(f.drives[1]->state, DriveState::kOperationEnabled);
  f.commands = {{hal::CommandMode::kPosition, -0.5, 0, 0},
                {hal::CommandMode::kPosition, -0.5, 0, 0}};

  f.bus.off = true;
  const std::size_t syncs_seen = f.drives[0]->controlwords_at_sync.size();
  EXPECT_EQ(f.cycle(), hal::Status::kFault);
  for (const hal::JointState& state : f.states) {
    EXPECT_NE(state.status_bits & hal::kJointCommLost, 0u);
  }
  for (int k = 0; k < 5; ++k) (void)f.cycle();
  EXPECT_EQ(f.drives[0]->controlwords_at_sync.size(), syncs_seen) << "nothing went out";
  EXPECT_EQ(f.group->counters().bus_faults, 1u);
  EXPECT_EQ(f.group->counters().tx_queue_full, 0u) << "bus-off is not a full queue";
  (void)f.group->request(DriveRequest::kFaultReset);
  (void)f.cycle();
  EXPECT_TRUE(f.group->bus_fault()) << "a reset while bus-off changes nothing";

  // The kernel restarted the controller; drive 1 rebooted meanwhile.
  f.bus.off = false;
  const std::int32_t held = f.drives[0]->position_counts;
  f.drives[1]->reboot();
  for (int k = 0; k < 5; ++k) EXPECT_EQ(f.cycle(), hal::Status::kFault) << "latched";
  // Held: no enable-operation controlword (the reset asked while bus-off disables it), the
  // target where the drive is.
  EXPECT_NE(f.drives[0]->controlwords_at_sync.back() & 0x000F, 0x000F);
  EXPECT_NE(f.drives[0]->state, DriveState::kOperationEnabled);
  EXPECT_EQ(f.drives[0]->targets_at_sync.back(), held);
  EXPECT_EQ(f.drives[0]->position_counts, held);

  (void)f.group->request(DriveRequest::kFaultReset);
  cycle_until(f, [&] { return f.group->counters().reconfigurations > 0; });
  EXPECT_FALSE(f.group->bus_fault());
  EXPECT_EQ(f.group->counters().reconfigurations, 1u) << "only the rebooted drive";
  EXPECT_EQ(f.group->counters().bus_faults, 1u);
  (void)f.cycle();
  EXPECT_EQ(f.cycle(), hal::Status::kOk);

  (void)f.group->request(DriveRequest::kEnable);
  cycle_until(f, [&] {
    return f.drives[0]->state == DriveState::kOperationEnabled &&
           f.drives[1]->state == DriveState::kOperationEnabled;
  });
  EXPECT_EQ(f.drives[0]->targets_at_sync.back(), held) << "re-enabled where it is";
  for (int k = 0; k < 3; ++k) (void)f.cycle();
  const auto units = cia402::Units::from(10.0, 10000);
  EXPECT_EQ(f.drives[0]->targets_at_sync.back(), units.to_counts(-0.5));
  EXPECT_EQ(f.drives[1]->targets_at_sync.back(), units.to_counts(-0.5));
}

TEST(CanJointGroup, EmergencyCodeIsKeptUntilFaultReset) {
  Fixture f;
  f.drives[0]->send_emcy(0x8611, 0x20);
  (void)f.cycle();
  EXPECT_EQ(f.states[0].error_code, 0x8611);
  f.drives[0]->send_emcy(0x0000, 0x00);  // "Error reset".
  (void)f.cycle();
  EXPECT_EQ(f.states[0].error_code, 0x8611);
  (void)f.group->request(DriveRequest::kFaultReset);
  (void)f.cycle();
  EXPECT_EQ(f.states[0].error_code, 0);
  EXPECT_EQ(f.group->counters().emergencies, 2u);
}

TEST(CanJointGroup, StaleAfterTheConfiguredMissedSyncs) {
  canopen::CanGroupSettings settings;
  settings.stale_after_missed_syncs = 3;
  Fixture f(1, settings);
  (void)f.cycle();
  f.drives[0]->answer_sync = false;
  (void)f.cycle();  // Reads the last answer.
  (void)f.cycle();  // Missed 1.
  (void)f.cycle();  // Missed 2.
  EXPECT_EQ(f.states[0].status_bits & hal::kJointStale, 0u);
  (void)f.cycle();  // Missed 3.
  EXPECT_NE(f.states[0].status_bits & hal::kJointStale, 0u);
  EXPECT_EQ(f.group->counters().missed_sync_answers, 3u);
  f.drives[0]->answer_sync = true;
  (void)f.cycle();
  (void)f.cycle();
  EXPECT_EQ(f.states[0].status_bits & hal::kJointStale, 0u);
}

TEST(CanJointGroup, MalformedUnexpectedAndLateFramesAreCountedAndIgnored) {
  Fixture f;
  (void)f.cycle();
  (void)f.cycle();
  hal::CanBus& intruder = f.network.add_endpoint("intruder");
  hal::CanFrame bad;
  bad.id = 0x18A;  // TPDO1 of node 10, 3 bytes instead of 6.
  bad.length = 3;
  ASSERT_EQ(intruder.send(bad), hal::Status::kOk);
  hal::CanFrame other;
  other.id = 0x1B2;  // TPDO1 of node 50, not in the group.
  other.length = 6;
  ASSERT_EQ(intruder.send(other), hal::Status::kOk);
  hal::CanFrame duplicate;
  duplicate.id = 0x18A;
  duplicate.length = 6;
  duplicate.data = {0x40, 0x00, 0x39, 0x30, 0x00, 0x00};
  ASSERT_EQ(intruder.send(duplicate), hal::Status::kOk);  // A second TPDO1 in one cycle.
  (void)f.cycle();
  const CanGroupCounters counters = f.group->counters();
  EXPECT_EQ(counters.malformed_frames, 1u);
  EXPECT_EQ(counters.unexpected_frames, 1u);
  EXPECT_EQ(counters.late_tpdos, 1u);
  EXPECT_EQ(f.states[0].drive_state, DriveState::kSwitchOnDisabled);
}

TEST(CanJointGroup, AFloodedBusIsReadAtMostACapPerCycleAndTheRestWaits) {
  Fixture f;
  (void)f.cycle();
  hal::CanBus& intruder = f.network.add_endpoint("intruder");
  hal::CanFrame other;
  other.id = 0x1B2;  // TPDO1 of node 50, not in the group.
  other.length = 6;
  const std::size_t cap = f.group->max_frames_per_read();
  const std::size_t flood = 2 * cap + 5;
  for (std::size_t i = 0; i < flood; ++i) ASSERT_EQ(intruder.send(other), hal::Status::kOk);
  (void)f.cycle();
  CanGroupCounters counters = f.group->counters();
  // The drive's answer to the previous SYNC was queued first; the flood fills the rest.
  EXPECT_EQ(counters.unexpected_frames, cap - 1) << "one cycle takes no more than the cap";
  EXPECT_EQ(counters.receive_cap_reached, 1u);
  (void)f.cycle();
  (void)f.cycle();
  (void)f.cycle();
  counters = f.group->counters();
  EXPECT_EQ(counters.unexpected_frames, flood) << "the rest is read in the next cycles";
  EXPECT_EQ(counters.receive_cap_reached, 2u);
  const std::uint64_t answered = counters.tpdos_received;
  (void)f.cycle();
  EXPECT_EQ(f.group->counters().tpdos_received, answered + 1) << "the drive is heard again";
}

TEST(CanJointGroup, OneSendBatchPerCycleCarriesRpdosThenSync) {
  Fixture f(2);
  hal::CanBus& probe = f.network.add_endpoint("probe");
  (void)f.cycle();
  std::vector<std::uint32_t> ids;
  hal::CanFrame frame;
  while (probe.receive(frame) == hal::Status::kOk) {
    if (frame.id < 0x180 || frame.id >= 0x200) ids.push_back(frame.id);  // Not the answers.
  }
  EXPECT_EQ(ids, (std::vector<std::uint32_t>{0x20A, 0x20B, 0x080}));
}

TEST(CanJointGroup, ReadWriteSyncDoNotAllocate) {
  canopen::CanGroupSettings settings;
  settings.heartbeat_period_s = 0.1;
  settings.effort_feedforward = true;
  settings.effort_feedback = true;
  Fixture f(2, settings);
  (void)f.group->request(DriveRequest::kEnable);
  f.commands[0].effort_feedforward_nm = 1.0;
  std::uint64_t allocations = 0;
  std::int64_t stamp_ns = 0;
  for (int k = 0; k < 3000; ++k) {
    if (k % 100 == 0) {
      for (auto& drive : f.drives) drive->send_heartbeat();
    }
    if (k == 1000) f.drives[0]->fault();
    if (k == 1100) f.drives[0]->send_emcy(0x7300, 0x01);
    if (k == 1500) (void)f.group->request(DriveRequest::kFaultReset);
    if (k == 1600) (void)f.group->request(DriveRequest::kEnable);
    f.drives[1]->answer_sync = k < 2000 || k > 2100;
    // Bus-off, a reboot, a reconfiguration that times out, one that completes, re-enable.
    if (k == 2200) f.bus.off = true;
    if (k == 2250) f.bus.off = false;
    if (k == 2260) f.drives[1]->reboot();
    if (k == 2270) f.drives[1]->answer_sdo = false;
    if (k == 2300) (void)f.group->request(DriveRequest::kFaultReset);
    if (k == 2450) f.drives[1]->answer_sdo = true;
    if (k == 2460) (void)f.group->request(DriveRequest::kFaultReset);
    if (k == 2700) (void)f.group->request(DriveRequest::kEnable);
    f.clock.advance_to_ns(f.clock.now_ns() + kPeriodNs);
    const std::uint64_t before = runtime::thread_allocation_count();
    (void)f.group->read(f.states, stamp_ns);
    (void)f.group->write(f.commands);
    (void)f.group->sync();
    allocations += runtime::thread_allocation_count() - before;
    f.step_drives();
  }
  EXPECT_EQ(allocations, 0u);
  EXPECT_EQ(f.drives[0]->state, DriveState::kOperationEnabled) << "the fault really happened";
  EXPECT_GT(f.group->counters().missed_sync_answers, 50u);
  EXPECT_EQ(f.group->counters().bus_faults, 1u);
  EXPECT_EQ(f.group->counters().reconfiguration_failures, 1u);
  EXPECT_EQ(f.group->counters().reconfigurations, 1u);
  EXPECT_EQ(f.drives[1]->state, DriveState::kOperationEnabled) << "re-enabled after the reboot";
  EXPECT_EQ(f.drives[0]->last_torque_offset, 50) << "1 N m / (10 * 2 N m)";
}

}  // namespace
}  // namespace cambio::canopen
