// The socketcan backend's lifecycle against the test's own drives on the in-process bus:
// configure (reset, boot-up, parameters, PDOs, read-back, start), enable through the group,
// deactivate (quick stop, disable, pre-operational), and the refusals.
#include "cambio/canopen/socketcan_backend.hpp"

#include <gtest/gtest.h>

#include <memory>
#include <vector>

#include "cambio/can/in_process_can_bus.hpp"
#include "cambio/hal/manual_clock.hpp"
#include "test_drive.hpp"

namespace cambio::canopen {
namespace {

/// Hands the backend an endpoint the network owns.
class BorrowedBus final : public hal::CanBus {
 public:
  explicit BorrowedBus(hal::CanBus& bus) : bus_(bus) {}
  const std::string& name() const override { return bus_.name(); }
  hal::Status send(const hal::CanFrame& frame) override { return bus_.send(frame); }
  hal::Status receive(hal::CanFrame& out) override { return bus_.receive(out); }
  hal::CanBusStatus status() const override { return bus_.status(); }

 private:
  hal::CanBus& bus_;
};

hal::HardwareInfo pan_tilt() {
  hal::HardwareInfo hardware;
  hardware.name = "pan_tilt";
  hal::JointGroupInfo group;
  group.name = "head";
  group.backend = "socketcan";
  group.rate_hz = 500.0;
  for (int k = 0; k < 2; ++k) {
    hal::JointInfo joint;
    joint.name = k == 0 ? "pan" : "tilt";
    joint.group = "head";
    joint.parent = "base";
    joint.limits = {-1.0, 1.0, 2.0, 10.0, 0.0};
    hardware.joints.push_back(joint);
    group.joints.push_back(joint.name);
    group.limits.push_back(joint.limits);
  }
  hardware.groups.push_back(group);
  return hardware;
}

/// pan_tilt()'s CANopen side: its group on bus can0 (interface vcan0), drives 1 and 2.
CanRigInfo pan_tilt_can() {
  CanRigInfo can_rig;
  can_rig.buses.push_back({"can0", "vcan0", 1'000'000, false, 0});
  can_rig.groups.push_back({"head", "can0", {}});
  for (int k = 0; k < 2; ++k) {
    JointDriveInfo drive;
    drive.node_id = 1 + k;
    drive.gear_ratio = 50.0;
    drive.encoder_counts_per_rev = 4096;
    can_rig.drives[k == 0 ? "pan" : "tilt"] = drive;
  }
  return can_rig;
}

struct Fixture {
  Fixture() {
    drives.push_back(std::make_unique<testing::TestDrive>(network.add_endpoint("d1"), 1));
    drives.push_back(std::make_unique<testing::TestDrive>(network.add_endpoint("d2"), 2));
    for (auto& drive : drives) drive->nmt_state = 0x05;  // Running from an earlier session.
    backend = make_backend();
  }
  /// A backend made by the registered factory for `hardware` and `can_rig` as they are now.
  std::unique_ptr<hal::Backend> make_backend() {
    SocketCanBackendOptions options;
    options.waiter = [this](hal::CanBus&, std::int64_t) { step(); };
    register_socketcan_backend(
        factory, can_rig,
        [this](const canopen::CanBusInfo& info) {
          opened.push_back(info.interface);
          return std::make_unique<BorrowedBus>(master);
        },
        options);
    hal::BackendContext context;
    context.clock = &clock;
    return factory.make("socketcan", hardware, context, "joint group 'head'");
  }
  void step() {
    for (auto& drive : drives) drive->step();
    clock.advance_to_ns(clock.now_ns() + 1'000'000);
  }

  hal::ManualClock clock{5'000'000'000};
  can::InProcessCanNetwork network{false, &clock};
  hal::CanBus& master = network.add_endpoint("master");
  std::vector<std::unique_ptr<testing::TestDrive>> drives;
  std::vector<std::string> opened;
  hal::HardwareInfo hardware = pan_tilt();
  CanRigInfo can_rig = pan_tilt_can();
  hal::BackendFactory factory;
  std::unique_ptr<hal::Backend> backend;
};

TEST(SocketCanBackend, ConfigureEnableDeactivate) {
  Fixture f;
  f.drives[1]->position_counts = -777;
  auto group = f.backend->make_joint_group("head");
  EXPECT_EQ(f.opened, (std::vector<std::string>{"vcan0"}));
  f.backend->configure();
  f.step();  // The drives take the NMT start.
  for (const auto& drive : f.drives) {
    EXPECT_EQ(drive->nmt_state, 0x05) << "started after configuration";
    EXPECT_EQ(drive->get(0x6060, 0), 8u);
    EXPECT_EQ(drive->get(0x60C2, 1), 2u) << "500 Hz = 2 * 10^-3 s";
    EXPECT_EQ(drive->get(0x1A00, 0), 2u);
    EXPECT_EQ(drive->get(0x1400, 1), 0x200u + (drive.get() == f.drives[0].get() ? 1u : 2u));
    // This drive has no PDO objects but those written to it: PDOs 2..4, which the layout does
    // not use, were asked for (an abort: no such object) and never written.
    for (const auto& write : drive->writes) {
      if (write.index < 0x1400 || write.index > 0x1BFF) continue;
      EXPECT_EQ(write.index & 0x3, 0) << std::hex << write.index << " only PDO 1 is touched";
    }
    EXPECT_FALSE(drive->has(0x1401, 1));
    EXPECT_FALSE(drive->has(0x1803, 1));
  }
  // The reset came first: the drive's first frame is NMT reset communication for it.
  EXPECT_EQ(f.drives[0]->received.front().id, 0x000u);
  EXPECT_EQ(f.drives[0]->received.front().data[0], 0x82);

  f.backend->activate();
  std::vector<hal::JointState> states(2);
  std::vector<hal::JointCommand> commands(2, {hal::CommandMode::kPosition, 0.0, 0, 0});
  std::int64_t stamp_ns = 0;
  ASSERT_EQ(group->read(states, stamp_ns), hal::Status::kOk);
  EXPECT_EQ(states[1].position_rad, cia402::Units::from(50.0, 4096).to_rad(-777))
      << "seeded from the drive at configure";
  (void)group->request(hal::DriveRequest::kEnable);
  for (int k = 0; k < 6; ++k) {
    f.clock.advance_to_ns(f.clock.now_ns() + 2'000'000);
    (void)group->read(states, stamp_ns);
    (void)group->write(commands);
    (void)group->sync();
    for (auto& drive : f.drives) drive->step();
  }
  EXPECT_EQ(f.drives[0]->state, hal::DriveState::kOperationEnabled);
  EXPECT_EQ(f.drives[1]->state, hal::DriveState::kOperationEnabled);

  f.backend->deactivate();
  for (auto& drive : f.drives) drive->step();
  for (const auto& drive : f.drives) {
    EXPECT_EQ(drive->state, hal::DriveState::kSwitchOnDisabled);
    EXPECT_EQ(drive->nmt_state, 0x7F) << "left pre-operational";
    const auto& words = drive->controlwords_at_sync;
    ASSERT_GE(words.size(), 2u);
    EXPECT_EQ(words[words.size() - 2], 0x0002) << "quick stop first";
    EXPECT_EQ(words.back(), 0x0000) << "then disable voltage";
  }
  f.backend->deactivate();  // Idempotent.
}

TEST(SocketCanBackend, AParameterTheDriveDidNotTakeRefusesToEnable) {
  Fixture f;
  f.drives[1]->clamp_on_write[testing::TestDrive::key(0x607D, 2)] = 1000;
  auto group = f.backend->make_joint_group("head");
  try {
    f.backend->configure();
    FAIL() << "configure must refuse";
  } catch (const std::runtime_error& error) {
    const std::string text = error.what();
    EXPECT_NE(text.find("node 2 (joint 'tilt'): object 0x607D:02 written 32595 (0x00007F53), "
                        "read back 1000 (0x000003E8)"),
              std::string::npos)
        << text;
  }
  EXPECT_EQ(f.drives[1]->nmt_state, 0x7F) << "never started";
}

TEST(SocketCanBackend, ASilentDriveIsNamed) {
  Fixture f;
  f.drives[0]->answer_sdo = false;
  auto group = f.backend->make_joint_group("head");
  try {
    f.backend->configure();
    FAIL() << "configure must refuse";
  } catch (const std::runtime_error& error) {
    const std::string text = error.what();
    EXPECT_NE(text.find("joint group 'head' on CAN bus 'can0'"), std::string::npos) << text;
    EXPECT_NE(text.find("joint 'pan': node 1: SDO upload of 0x1000:00: no answer"),
              std::string::npos)
        << text;
  }
}

TEST(SocketCanBackend, ARebootedDriveGetsItsParametersAndPdosAgainOnFaultReset) {
  Fixture f;
  f.can_rig.groups[0].settings.effort_feedforward = true;
  f.drives[1]->set(0x6076, 0, 1500, 4);
  auto backend = f.make_backend();
  auto group = backend->make_joint_group("head");
  backend->configure();
  f.step();
  const std::vector<testing::TestDrive::Write> configured = f.drives[1]->writes;
  backend->activate();
  std::vector<hal::JointState> states(2);
  std::vector<hal::JointCommand> commands(2, {hal::CommandMode::kPosition, 0.0, 0, 1.5});
  const auto cycle = [&] {
    f.clock.advance_to_ns(f.clock.now_ns() + 2'000'000);
    std::int64_t stamp_ns = 0;
    const hal::Status status = group->read(states, stamp_ns);
    (void)group->write(commands);
    (void)group->sync();
    for (auto& drive : f.drives) drive->step();
    return status;
  };
  (void)group->request(hal::DriveRequest::kEnable);
  for (int k = 0; k < 6; ++k) (void)cycle();
  // 1.5 N m at the joint / gear 50 = 0.03 N m at the motor = 20 per mille of 1.5 N m.
  EXPECT_EQ(f.drives[1]->last_torque_offset, 20);

  f.drives[1]->reboot();
  EXPECT_EQ(cycle(), hal::Status::kFault);
  (void)group->request(hal::DriveRequest::kFaultReset);
  const auto* can_group = dynamic_cast<SocketCanBackend&>(*backend).group("head");
  for (int k = 0; k < 200 && can_group->counters().reconfigurations == 0; ++k) (void)cycle();
  ASSERT_EQ(can_group->counters().reconfigurations, 1u)
      << can_group->last_reconfiguration_error().text.data();
  ASSERT_EQ(f.drives[1]->writes.size(), configured.size()) << "parameters and PDOs, as configured";
  for (std::size_t i = 0; i < configured.size(); ++i) {
    EXPECT_EQ(f.drives[1]->writes[i].index, configured[i].index) << i;
    EXPECT_EQ(f.drives[1]->writes[i].value, configured[i].value) << i;
  }
  EXPECT_EQ(f.drives[1]->get(0x6060, 0), 8u);
  (void)group->request(hal::DriveRequest::kEnable);
  for (int k = 0; k < 8; ++k) (void)cycle();
  EXPECT_EQ(f.drives[1]->state, hal::DriveState::kOperationEnabled);
  EXPECT_EQ(cycle(), hal::Status::kOk);
}

TEST(SocketCanBackend, EffortWithoutARatedTorqueIsRefused) {
  Fixture f;
  f.can_rig.groups[0].settings.effort_feedforward = true;
  f.drives[0]->set(0x6076, 0, 0, 4);
  auto backend = f.make_backend();
  auto group = backend->make_joint_group("head");
  try {
    backend->configure();
    FAIL() << "configure must refuse";
  } catch (const std::runtime_error& error) {
    EXPECT_NE(std::string(error.what()).find("joint 'pan': node 1: rated torque (0x6076:00) is 0"),
              std::string::npos)
        << error.what();
  }
}

TEST(SocketCanBackend, TwoGroupsOnOneBusAreRefused) {
  Fixture f;
  hal::JointGroupInfo second = f.hardware.groups[0];
  second.name = "other";
  f.hardware.groups.push_back(second);
  hal::BackendContext context;
  context.clock = &f.clock;
  auto backend = f.factory.make("socketcan", f.hardware, context, "test");
  auto head = backend->make_joint_group("head");
  EXPECT_THROW((void)backend->make_joint_group("other"), std::runtime_error);
  EXPECT_THROW((void)backend->make_camera("left"), hal::BackendUnavailable);
}

}  // namespace
}  // namespace cambio::canopen
