// The virtual rig built from the shipped pan-tilt rig: one drive per CAN joint on the group's
// bus, answering raw CANopen frames on an in-process bus.
#include <stdexcept>

#include "cambio/config/rig_loader.hpp"
#include "cambio/virtual_rig/virtual_rig.hpp"
#include "drive_test_support.hpp"

namespace cambio::virtual_rig::test {
namespace {

/// Hands the rig an endpoint of a network the test owns.
class EndpointRef final : public hal::CanBus {
 public:
  explicit EndpointRef(hal::CanBus& bus) : bus_(bus) {}
  const std::string& name() const override { return bus_.name(); }
  hal::Status send(const hal::CanFrame& frame) override { return bus_.send(frame); }
  hal::Status receive(hal::CanFrame& out) override { return bus_.receive(out); }
  hal::CanBusStatus status() const override { return bus_.status(); }

 private:
  hal::CanBus& bus_;
};

config::RigConfig pan_tilt() {
  return config::load_rig(std::string(CAMBIO_SOURCE_DIR) + "/firmware_config/rigs/pan_tilt.yaml");
}

TEST(VirtualRig, OneDrivePerCanJointOnTheGroupsBus) {
  can::InProcessCanNetwork network;
  hal::CanBus& master = network.add_endpoint("master");
  std::vector<std::string> opened;
  VirtualRig rig(pan_tilt(), [&](const canopen::CanBusInfo& info) {
    opened.push_back(info.name + "=" + info.interface);
    return std::make_unique<EndpointRef>(network.add_endpoint(info.name));
  });
  ASSERT_EQ(opened, std::vector<std::string>{"can0=can0"});
  ASSERT_EQ(rig.bus_count(), 1u);
  ASSERT_EQ(rig.drive_count(0), 2u);
  EXPECT_EQ(rig.joint_name(0, 0), "pan");
  EXPECT_EQ(rig.drive(0, 0).node_id(), 1);
  EXPECT_EQ(rig.joint_name(0, 1), "tilt");
  EXPECT_EQ(rig.drive(0, 1).node_id(), 2);

  rig.power_on(0);
  rig.process(0, 0);
  hal::CanFrame f;
  std::vector<std::uint32_t> boot_ups;
  while (master.receive(f) == hal::Status::kOk) boot_ups.push_back(f.id);
  EXPECT_EQ(boot_ups, (std::vector<std::uint32_t>{0x701, 0x702}));

  // Tilt's upper limit, 60 deg, in its drive's counts (gear 50, 4096 counts per motor turn).
  ASSERT_EQ(master.send(frame(0x602, {0x40, 0x7D, 0x60, 0x02, 0, 0, 0, 0})), hal::Status::kOk);
  EXPECT_EQ(rig.process(0, 1000), 1u);
  ASSERT_EQ(master.receive(f), hal::Status::kOk);
  EXPECT_EQ(f.id, 0x582u);
  EXPECT_EQ(le_i32(f, 4), static_cast<std::int32_t>(std::lround(50.0 * 4096.0 / 6.0)));
}

TEST(VirtualRig, RefusesFaultsForNodesItDoesNotHave) {
  can::InProcessCanNetwork network;
  VirtualRigOptions options;
  options.faults.push_back(parse_fault("emcy,node=9"));
  try {
    VirtualRig rig(
        pan_tilt(),
        [&](const canopen::CanBusInfo& info) {
          return std::make_unique<EndpointRef>(network.add_endpoint(info.name));
        },
        options);
    FAIL() << "accepted a fault for node 9";
  } catch (const std::invalid_argument& error) {
    EXPECT_NE(std::string(error.what()).find("node 9"), std::string::npos) << error.what();
  }
}

TEST(VirtualRig, ABusThatCannotOpenStopsConstruction) {
  EXPECT_THROW(VirtualRig(pan_tilt(),
                          [](const canopen::CanBusInfo& info) -> std::unique_ptr<hal::CanBus> {
                            throw std::runtime_error("no interface " + info.interface);
                          }),
               std::runtime_error);
}

}  // namespace
}  // namespace cambio::virtual_rig::test
