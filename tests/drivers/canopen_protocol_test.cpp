// The CANopen / CiA 402 vocabulary against the standards' own tables (CiA 301 predefined
// connection set, CiA 402-2 Tables 29-30 and Figure 4), and the in-process bus.
#include <array>
#include <cstdint>

#include <gtest/gtest.h>

#include "cambio/can/in_process_can_bus.hpp"
#include "cambio/canopen/cia402.hpp"
#include "cambio/canopen/pdo_layout.hpp"
#include "cambio/canopen/protocol.hpp"

namespace cambio::canopen {
namespace {

using hal::DriveRequest;
using hal::DriveState;

TEST(CanopenProtocol, PredefinedConnectionSet) {
  EXPECT_EQ(emcy_cob_id(5), 0x085u);
  EXPECT_EQ(tpdo_cob_id(1, 5), 0x185u);
  EXPECT_EQ(tpdo_cob_id(4, 127), 0x4FFu);
  EXPECT_EQ(rpdo_cob_id(1, 1), 0x201u);
  EXPECT_EQ(rpdo_cob_id(2, 1), 0x301u);
  EXPECT_EQ(sdo_response_cob_id(3), 0x583u);
  EXPECT_EQ(sdo_request_cob_id(3), 0x603u);
  EXPECT_EQ(heartbeat_cob_id(127), 0x77Fu);
  EXPECT_EQ(node_of(0x58A), 10);
  EXPECT_EQ(function_of(0x58A), 0x580u);
}

TEST(CanopenProtocol, PdoMappingEntryMatchesCia301Layout) {
  // CiA 301 §7.4.8 example layout: 0x60400010 maps controlword, 16 bits.
  EXPECT_EQ(pdo_mapping_entry(cia402::kControlword, 16), 0x6040'0010u);
  EXPECT_EQ(pdo_mapping_entry({0x607D, 2}, 32), 0x607D'0220u);
  EXPECT_EQ(mapped_object(0x607D'0220u), (ObjectAddress{0x607D, 2}));
  EXPECT_EQ(mapped_bits(0x607D'0220u), 32);
}

TEST(CanopenProtocol, LittleEndianFieldsAndSignExtension) {
  std::array<std::uint8_t, 8> data{};
  put_le(data, 2, 4, 0x1234'5678u);
  EXPECT_EQ(data[2], 0x78);
  EXPECT_EQ(data[5], 0x12);
  EXPECT_EQ(get_le(data, 2, 4), 0x1234'5678u);
  EXPECT_EQ(sign_extend(0xFFFFu, 2), -1);
  EXPECT_EQ(sign_extend(0x7FFFu, 2), 32767);
  EXPECT_EQ(sign_extend(0x80u, 1), -128);
  EXPECT_EQ(sign_extend(0xFFFF'FFFEu, 4), -2);
}

TEST(CanopenProtocol, AbortCodesHaveTheirCia301Names) {
  EXPECT_EQ(sdo_abort_name(0x0602'0000), "object does not exist in the object dictionary");
  EXPECT_EQ(sdo_abort_name(0x0601'0002), "attempt to write a read only object");
  EXPECT_EQ(sdo_abort_name(0x1234'5678), "");
}

TEST(Cia402, StatuswordPatternsOfTable30) {
  // Typical statuswords seen on real drives, with the don't-care bits set.
  EXPECT_EQ(cia402::drive_state_of(0x0250), DriveState::kSwitchOnDisabled);
  EXPECT_EQ(cia402::drive_state_of(0x0231), DriveState::kReadyToSwitchOn);
  EXPECT_EQ(cia402::drive_state_of(0x0233), DriveState::kSwitchedOn);
  EXPECT_EQ(cia402::drive_state_of(0x1637), DriveState::kOperationEnabled);
  EXPECT_EQ(cia402::drive_state_of(0x0217), DriveState::kQuickStopActive);
  EXPECT_EQ(cia402::drive_state_of(0x021F), DriveState::kFaultReactionActive);
  EXPECT_EQ(cia402::drive_state_of(0x0218), DriveState::kFault);
  EXPECT_EQ(cia402::drive_state_of(0x0000), DriveState::kNotReadyToSwitchOn);
  for (const DriveState state :
       {DriveState::kNotReadyToSwitchOn, DriveState::kSwitchOnDisabled,
        DriveState::kReadyToSwitchOn, DriveState::kSwitchedOn, DriveState::kOperationEnabled,
        DriveState::kQuickStopActive, DriveState::kFaultReactionActive, DriveState::kFault}) {
    EXPECT_EQ(cia402::drive_state_of(cia402::statusword_of(state)), state) << to_string(state);
  }
}

TEST(Cia402, ControlwordCommandsOfTable29) {
  using cia402::Command;
  EXPECT_EQ(cia402::decode_controlword(0x0006, 0), Command::kShutdown);
  EXPECT_EQ(cia402::decode_controlword(0x0007, 0), Command::kSwitchOn);
  EXPECT_EQ(cia402::decode_controlword(0x000F, 0), Command::kEnableOperation);
  EXPECT_EQ(cia402::decode_controlword(0x0000, 0x000F), Command::kDisableVoltage);
  EXPECT_EQ(cia402::decode_controlword(0x000D, 0), Command::kDisableVoltage);
  EXPECT_EQ(cia402::decode_controlword(0x0002, 0), Command::kQuickStop);
  EXPECT_EQ(cia402::decode_controlword(0x000B, 0), Command::kQuickStop);
  EXPECT_EQ(cia402::decode_controlword(0x0080, 0x0000), Command::kFaultReset);
  EXPECT_EQ(cia402::decode_controlword(0x0080, 0x0080), Command::kNone);  // No edge.
}

// The master's controlwords walk the drive's state machine to what each request asks, and
// agree with the HAL's request-level state machine one transition at a time.
TEST(Cia402, MasterControlwordsDriveTheDriveStateMachine) {
  struct Case {
    DriveState from;
    DriveRequest request;
    DriveState to;
  };
  for (const Case& c :
       {Case{DriveState::kSwitchOnDisabled, DriveRequest::kEnable, DriveState::kOperationEnabled},
        Case{DriveState::kOperationEnabled, DriveRequest::kDisable, DriveState::kSwitchOnDisabled},
        Case{DriveState::kOperationEnabled, DriveRequest::kQuickStop, DriveState::kQuickStopActive},
        Case{DriveState::kQuickStopActive, DriveRequest::kEnable, DriveState::kOperationEnabled},
        Case{DriveState::kFault, DriveRequest::kFaultReset, DriveState::kSwitchOnDisabled}}) {
    DriveState state = c.from;
    std::uint16_t previous = 0x000F;
    for (int cycle = 0; cycle < 6 && state != c.to; ++cycle) {
      const std::uint16_t controlword = cia402::controlword_toward(state, c.request, previous);
      const DriveState next =
          cia402::drive_state_after(state, cia402::decode_controlword(controlword, previous));
      if (next != state) {
        EXPECT_EQ(next, hal::next_drive_state(state, c.request));
      }
      state = next;
      previous = controlword;
    }
    EXPECT_EQ(state, c.to) << to_string(c.from) << " + " << to_string(c.request);
  }
}

TEST(Cia402, EnableIsRefusedWhileFaulted) {
  const std::uint16_t controlword =
      cia402::controlword_toward(DriveState::kFault, DriveRequest::kEnable, 0);
  EXPECT_EQ(
      cia402::drive_state_after(DriveState::kFault, cia402::decode_controlword(controlword, 0)),
      DriveState::kFault);
}

TEST(Cia402, UnitsFromGearAndEncoder) {
  // 4096 counts per motor turn, 50:1 gear: one joint turn is 204800 counts.
  const auto units = cia402::Units::from(50.0, 4096);
  EXPECT_EQ(units.to_counts(2.0 * std::numbers::pi), 204800);
  EXPECT_EQ(units.to_counts(-std::numbers::pi / 2.0), -51200);
  EXPECT_NEAR(units.to_rad(51200), std::numbers::pi / 2.0, 1e-12);
  EXPECT_EQ(units.to_counts(1e30), INT32_MAX);
}

TEST(InProcessCanBus, DeliversToEveryOtherEndpointAndCountsDrops) {
  can::InProcessCanNetwork network;
  hal::CanBus& master = network.add_endpoint("master", 4);
  hal::CanBus& drive = network.add_endpoint("drive", 2);
  hal::CanFrame frame;
  frame.id = 0x201;
  frame.length = 2;
  frame.data[0] = 0x0F;
  for (int i = 0; i < 3; ++i) EXPECT_EQ(master.send(frame), hal::Status::kOk);
  hal::CanFrame received;
  EXPECT_EQ(master.receive(received), hal::Status::kNoNewData);  // No echo to the sender.
  EXPECT_EQ(drive.receive(received), hal::Status::kOk);
  EXPECT_EQ(received.id, 0x201u);
  EXPECT_EQ(received.data[0], 0x0F);
  EXPECT_EQ(drive.receive(received), hal::Status::kOk);
  EXPECT_EQ(drive.receive(received), hal::Status::kNoNewData);
  EXPECT_EQ(drive.status().frames_dropped, 1u);
  hal::CanFrame fd_frame = frame;
  fd_frame.fd = true;
  EXPECT_EQ(master.send(fd_frame), hal::Status::kRejected);  // Classic network.
}

// The minimum set fits one frame each way; optional objects go to a second PDO, never beyond
// a classic frame's 8 bytes.
TEST(PdoLayout, MinimumSetAndOptionalObjects) {
  const PdoLayout minimal = pdo_layout(hal::CommandMode::kPosition, {});
  EXPECT_EQ(minimal.rpdos[0].bytes(), 6);
  EXPECT_TRUE(minimal.rpdos[1].empty());
  EXPECT_EQ(minimal.tpdos[0].bytes(), 6);
  EXPECT_TRUE(minimal.tpdos[1].empty());
  canopen::CanGroupSettings all;
  all.velocity_feedforward = all.effort_feedforward = true;
  all.velocity_feedback = all.effort_feedback = true;
  const PdoLayout full = pdo_layout(hal::CommandMode::kPosition, all);
  EXPECT_EQ(full.rpdos[1].bytes(), 6);
  EXPECT_EQ(full.tpdos[1].bytes(), 6);
  const PdoLayout velocity = pdo_layout(hal::CommandMode::kVelocity, all);
  EXPECT_EQ(velocity.rpdos[0].entries[1].object, cia402::kTargetVelocity);
  EXPECT_EQ(velocity.rpdos[1].bytes(), 2);  // CSV has no velocity offset.
}

}  // namespace
}  // namespace cambio::canopen
