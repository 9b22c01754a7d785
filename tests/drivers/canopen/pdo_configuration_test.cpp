// PDO configuration and drive parameters: the exact SDO write sequence CiA 301 §7.5.2.35-38
// prescribes, written out here by hand, what reaches a drive (the test's own SDO server), and
// the read-back that refuses a drive which did not take a value.
#include "cambio/canopen/pdo_configuration.hpp"

#include <gtest/gtest.h>

#include <vector>

#include "cambio/can/in_process_can_bus.hpp"
#include "cambio/canopen/drive_parameters.hpp"
#include "cambio/canopen/pdo_codec.hpp"
#include "cambio/hal/manual_clock.hpp"
#include "test_drive.hpp"

namespace cambio::canopen {
namespace {

std::vector<ObjectWrite> expected_csp_minimal_node3() {
  return {
      // RPDO1: invalidate, clear, map controlword + target position, count, SYNC type, validate.
      {{0x1400, 1}, 0x8000'0203, 4},
      {{0x1600, 0}, 0, 1},
      {{0x1600, 1}, 0x6040'0010, 4},
      {{0x1600, 2}, 0x607A'0020, 4},
      {{0x1600, 0}, 2, 1},
      {{0x1400, 2}, 1, 1},
      {{0x1400, 1}, 0x0000'0203, 4},
      // RPDO2 unused: left invalid and empty.
      {{0x1401, 1}, 0x8000'0303, 4},
      {{0x1601, 0}, 0, 1},
      // RPDO3, RPDO4 (0x400, 0x500 + node): invalidated, nothing more.
      {{0x1402, 1}, 0x8000'0403, 4},
      {{0x1403, 1}, 0x8000'0503, 4},
      // TPDO1: statusword + position actual; bit 30 = no RTR.
      {{0x1800, 1}, 0xC000'0183, 4},
      {{0x1A00, 0}, 0, 1},
      {{0x1A00, 1}, 0x6041'0010, 4},
      {{0x1A00, 2}, 0x6064'0020, 4},
      {{0x1A00, 0}, 2, 1},
      {{0x1800, 2}, 1, 1},
      {{0x1800, 1}, 0x4000'0183, 4},
      {{0x1801, 1}, 0xC000'0283, 4},
      {{0x1A01, 0}, 0, 1},
      // TPDO3, TPDO4 (0x380, 0x480 + node).
      {{0x1802, 1}, 0xC000'0383, 4},
      {{0x1803, 1}, 0xC000'0483, 4},
  };
}

TEST(PdoConfiguration, PdosTheDriveLacksAreNotTouched) {
  // A drive with one PDO each way: only RPDO1 and TPDO1 are written.
  PdoPresence one_each;
  one_each.rpdos = {true, false, false, false};
  one_each.tpdos = {true, false, false, false};
  const auto writes = pdo_configuration_writes(
      3, pdo_layout(hal::CommandMode::kPosition, canopen::CanGroupSettings{}), one_each);
  std::vector<ObjectWrite> expected;
  for (const ObjectWrite& write : expected_csp_minimal_node3()) {
    const std::uint16_t index = write.object.index;
    if (index == 0x1400 || index == 0x1600 || index == 0x1800 || index == 0x1A00) {
      expected.push_back(write);
    }
  }
  EXPECT_EQ(writes, expected);
}

TEST(PdoConfiguration, MinimalCspLayoutIsWrittenInCia301Order) {
  const PdoLayout layout = pdo_layout(hal::CommandMode::kPosition, canopen::CanGroupSettings{});
  EXPECT_EQ(pdo_configuration_writes(3, layout), expected_csp_minimal_node3());
}

TEST(PdoConfiguration, FeedbackAndFeedForwardAddTheirPdos) {
  canopen::CanGroupSettings settings;
  settings.velocity_feedforward = true;
  settings.velocity_feedback = true;
  settings.effort_feedback = true;
  const auto writes =
      pdo_configuration_writes(1, pdo_layout(hal::CommandMode::kPosition, settings));
  const auto has = [&](ObjectWrite write) {
    return std::find(writes.begin(), writes.end(), write) != writes.end();
  };
  EXPECT_TRUE(has({{0x1601, 1}, 0x60B1'0020, 4}));
  EXPECT_TRUE(has({{0x1601, 0}, 1, 1}));
  EXPECT_TRUE(has({{0x1A01, 1}, 0x606C'0020, 4}));
  EXPECT_TRUE(has({{0x1A01, 2}, 0x6077'0010, 4}));
  EXPECT_TRUE(has({{0x1801, 1}, 0x4000'0281, 4}));
}

struct Bench {
  hal::ManualClock clock;
  can::InProcessCanNetwork network{false, &clock};
  hal::CanBus& master = network.add_endpoint("master");
  testing::TestDrive drive{network.add_endpoint("drive"), 3};
  BusPump pump{master, clock, [this](hal::CanBus&, std::int64_t) {
                 drive.step();
                 clock.advance_to_ns(clock.now_ns() + 1'000'000);
               }};
};

TEST(PdoConfiguration, TheDriveReceivesExactlyTheSequence) {
  Bench bench;
  const auto writes = pdo_configuration_writes(
      3, pdo_layout(hal::CommandMode::kPosition, canopen::CanGroupSettings{}));
  write_objects(bench.pump, 3, writes, 0.1);
  const auto expected = expected_csp_minimal_node3();
  ASSERT_EQ(bench.drive.writes.size(), expected.size());
  for (std::size_t i = 0; i < expected.size(); ++i) {
    EXPECT_EQ(bench.drive.writes[i].index, expected[i].object.index) << i;
    EXPECT_EQ(bench.drive.writes[i].subindex, expected[i].object.subindex) << i;
    EXPECT_EQ(bench.drive.writes[i].value, expected[i].value) << i;
    EXPECT_EQ(bench.drive.writes[i].bytes, expected[i].bytes) << i;
  }
  // The first request on the wire: expedited download of 4 bytes to 0x1400:01.
  const hal::CanFrame& first = bench.drive.received.front();
  EXPECT_EQ(first.id, 0x603u);
  const std::vector<std::uint8_t> bytes(first.data.begin(), first.data.begin() + 8);
  EXPECT_EQ(bytes, (std::vector<std::uint8_t>{0x23, 0x00, 0x14, 0x01, 0x03, 0x02, 0x00, 0x80}));
  EXPECT_TRUE(verify_objects(bench.pump, 3, "joint 'pan'", writes, 0.1).empty());
}

hal::JointInfo pan_joint() {
  hal::JointInfo joint;
  joint.name = "pan";
  joint.limits = {-1.0, 2.0, 3.0, 10.0, 0.0};
  return joint;
}

canopen::JointDriveInfo pan_drive() {
  canopen::JointDriveInfo drive;
  drive.node_id = 3;
  drive.gear_ratio = 100.0;
  drive.encoder_counts_per_rev = 4096;
  drive.following_error_window_rad = 0.01;
  return drive;
}

TEST(DriveParameters, ValuesFollowTheRigInDriveUnits) {
  hal::JointGroupInfo group;
  group.name = "head";
  canopen::CanGroupSettings settings;
  settings.heartbeat_period_s = 0.05;
  const auto writes = drive_parameter_writes(pan_joint(), pan_drive(), group, settings, 1000.0);
  const double counts_per_rad = 100.0 * 4096.0 / (2.0 * 3.14159265358979323846);  // 65189.9
  const auto find = [&](ObjectAddress object) {
    for (const auto& write : writes) {
      if (write.object == object) return write.value;
    }
    ADD_FAILURE() << "not written: " << object.index << ":" << int(object.subindex);
    return 0u;
  };
  EXPECT_EQ(find({0x6060, 0}), 8u);
  EXPECT_EQ(static_cast<std::int32_t>(find({0x607D, 1})), -std::lround(counts_per_rad));
  EXPECT_EQ(static_cast<std::int32_t>(find({0x607D, 2})), std::lround(2.0 * counts_per_rad));
  EXPECT_EQ(find({0x607F, 0}), static_cast<std::uint32_t>(std::lround(3.0 * counts_per_rad)));
  EXPECT_EQ(find({0x6065, 0}), static_cast<std::uint32_t>(std::lround(0.01 * counts_per_rad)));
  EXPECT_EQ(find({0x1017, 0}), 50u);
  EXPECT_EQ(find({0x60C2, 1}), 1u);
  EXPECT_EQ(static_cast<std::int8_t>(find({0x60C2, 2})), -3);
}

TEST(DriveParameters, InterpolationPeriodPicksAnExactRepresentation) {
  EXPECT_EQ(interpolation_period(0.001).value, 1);
  EXPECT_EQ(interpolation_period(0.001).index, -3);
  EXPECT_EQ(interpolation_period(0.0025).value, 25);
  EXPECT_EQ(interpolation_period(0.0025).index, -4);
  EXPECT_EQ(interpolation_period(0.004).value, 4);
  EXPECT_EQ(interpolation_period(0.004).index, -3);
  EXPECT_THROW((void)interpolation_period(0.0), std::invalid_argument);
}

TEST(DriveParameters, AMismatchNamesNodeObjectWrittenAndRead) {
  Bench bench;
  hal::JointGroupInfo group;
  group.name = "head";
  const auto writes = drive_parameter_writes(pan_joint(), pan_drive(), group, {}, 1000.0);
  // The drive caps its max profile velocity at 100000 counts/s.
  bench.drive.clamp_on_write[testing::TestDrive::key(0x607F, 0)] = 100000;
  write_objects(bench.pump, 3, writes, 0.1);
  const auto mismatches = verify_objects(bench.pump, 3, "joint 'pan'", writes, 0.1);
  ASSERT_EQ(mismatches.size(), 1u);
  EXPECT_EQ(mismatches[0],
            "node 3 (joint 'pan'): object 0x607F:00 written 195570 (0x0002FBF2), read back "
            "100000 (0x000186A0)");
}

TEST(PdoCodec, PacksAndUnpacksLittleEndianInMappingOrder) {
  const PdoLayout layout = pdo_layout(hal::CommandMode::kPosition, canopen::CanGroupSettings{});
  DriveTargets targets;
  targets.controlword = 0x000F;
  targets.target_position_counts = -2;
  hal::CanFrame frame;
  pack_pdo(
      layout.rpdos[0], 0x203, [&](ObjectAddress o) { return raw_target(targets, o); }, frame);
  EXPECT_EQ(frame.id, 0x203u);
  ASSERT_EQ(frame.length, 6);
  EXPECT_EQ(std::vector<std::uint8_t>(frame.data.begin(), frame.data.begin() + 6),
            (std::vector<std::uint8_t>{0x0F, 0x00, 0xFE, 0xFF, 0xFF, 0xFF}));

  hal::CanFrame tpdo;
  tpdo.length = 6;
  tpdo.data = {0x37, 0x02, 0x10, 0x00, 0x00, 0x80};
  DriveFeedback feedback;
  ASSERT_TRUE(
      unpack_pdo(layout.tpdos[0], tpdo, [&](ObjectAddress o, std::uint32_t raw, std::size_t n) {
        store_feedback(feedback, o, raw, n);
      }));
  EXPECT_EQ(feedback.statusword, 0x0237);
  EXPECT_EQ(feedback.position_counts, static_cast<std::int32_t>(0x8000'0010u));
  tpdo.length = 5;
  EXPECT_FALSE(unpack_pdo(layout.tpdos[0], tpdo, [](ObjectAddress, std::uint32_t, std::size_t) {}));
}

}  // namespace
}  // namespace cambio::canopen
