// Error frames decoded into bus state and counters, with frames built per <linux/can/error.h>
// (the kernel's layout: class bits in the id, controller status in data[1], TEC/REC in
// data[6]/data[7]) and, for one, taken from a candump -L line.
#include "cambio/can/can_error_frame.hpp"

#include <gtest/gtest.h>
#include <linux/can.h>
#include <linux/can/error.h>

#include "cambio/can/candump_log.hpp"

namespace cambio::can {
namespace {

hal::CanFrame error_frame(std::uint32_t error_class, std::uint8_t controller = 0,
                          std::uint8_t tec = 0, std::uint8_t rec = 0) {
  hal::CanFrame frame;
  frame.error_frame = true;
  frame.id = error_class;
  frame.length = CAN_ERR_DLC;
  frame.data[1] = controller;
  frame.data[6] = tec;
  frame.data[7] = rec;
  return frame;
}

TEST(CanErrorFrame, ControllerWarningCarriesStateAndCounters) {
  const auto report = decode_can_error_frame(
      error_frame(CAN_ERR_CRTL | CAN_ERR_CNT, CAN_ERR_CRTL_TX_WARNING, 97, 12));
  ASSERT_TRUE(report.state);
  EXPECT_EQ(*report.state, hal::CanBusState::kErrorWarning);
  EXPECT_EQ(report.tx_error_count, 97);
  EXPECT_EQ(report.rx_error_count, 12);
  EXPECT_EQ(report.error_class, CAN_ERR_CRTL | CAN_ERR_CNT);
}

TEST(CanErrorFrame, PassiveWinsOverWarningInEitherDirection) {
  auto report = decode_can_error_frame(
      error_frame(CAN_ERR_CRTL, CAN_ERR_CRTL_RX_PASSIVE | CAN_ERR_CRTL_TX_WARNING, 100, 130));
  EXPECT_EQ(report.state, hal::CanBusState::kErrorPassive);
  report = decode_can_error_frame(error_frame(CAN_ERR_CRTL, CAN_ERR_CRTL_RX_WARNING));
  EXPECT_EQ(report.state, hal::CanBusState::kErrorWarning);
  report = decode_can_error_frame(error_frame(CAN_ERR_CRTL, CAN_ERR_CRTL_ACTIVE));
  EXPECT_EQ(report.state, hal::CanBusState::kErrorActive);
}

TEST(CanErrorFrame, OverflowAloneReportsNoState) {
  const auto report = decode_can_error_frame(error_frame(CAN_ERR_CRTL, CAN_ERR_CRTL_RX_OVERFLOW));
  EXPECT_FALSE(report.state);
  EXPECT_TRUE(report.rx_overflow);
  EXPECT_FALSE(report.tx_overflow);
}

TEST(CanErrorFrame, ProtocolErrorWithCounterFlagUpdatesCountersOnly) {
  const auto report = decode_can_error_frame(error_frame(CAN_ERR_PROT | CAN_ERR_CNT, 0, 8, 1));
  EXPECT_FALSE(report.state);
  EXPECT_EQ(report.tx_error_count, 8);
  EXPECT_EQ(report.rx_error_count, 1);
  // Without CAN_ERR_CNT (or CAN_ERR_CRTL) data[6]/data[7] mean nothing.
  const auto bare = decode_can_error_frame(error_frame(CAN_ERR_PROT, 0, 8, 1));
  EXPECT_FALSE(bare.tx_error_count);
  EXPECT_FALSE(bare.rx_error_count);
}

TEST(CanErrorFrame, BusOffIsCountedOnceAndRestartReturnsToActive) {
  hal::CanBusStatus status;
  status.state = hal::CanBusState::kErrorActive;
  apply_can_error_frame(decode_can_error_frame(error_frame(CAN_ERR_BUSOFF)), status);
  apply_can_error_frame(decode_can_error_frame(error_frame(CAN_ERR_BUSOFF)), status);
  EXPECT_EQ(status.state, hal::CanBusState::kBusOff);
  EXPECT_EQ(status.bus_off_count, 1u);
  apply_can_error_frame(decode_can_error_frame(error_frame(CAN_ERR_RESTARTED)), status);
  EXPECT_EQ(status.state, hal::CanBusState::kErrorActive);
  apply_can_error_frame(
      decode_can_error_frame(error_frame(CAN_ERR_BUSOFF | CAN_ERR_CRTL, CAN_ERR_CRTL_TX_PASSIVE)),
      status);
  EXPECT_EQ(status.state, hal::CanBusState::kBusOff);
  EXPECT_EQ(status.bus_off_count, 2u);
  EXPECT_EQ(status.error_frames, 4u);
}

TEST(CanErrorFrame, NotTrustedWhenShortOrNotAnErrorFrame) {
  hal::CanFrame short_frame = error_frame(CAN_ERR_BUSOFF);
  short_frame.length = 4;
  EXPECT_FALSE(decode_can_error_frame(short_frame).state);
  hal::CanFrame data_frame = error_frame(CAN_ERR_BUSOFF);
  data_frame.error_frame = false;
  EXPECT_FALSE(decode_can_error_frame(data_frame).state);
  EXPECT_EQ(decode_can_error_frame(data_frame).error_class, 0u);
}

TEST(CanErrorFrame, DecodesTheLineCandumpPrintsForAControllerProblem) {
  // candump -L prints an error frame as CAN_ERR_FLAG | class, then the 8 data bytes:
  // CAN_ERR_CRTL (4), data[1] = RX_PASSIVE (0x10), TEC 0x60, REC 0x80.
  const hal::CanFrame frame = parse_candump_frame("20000004#0010000000006080");
  const auto report = decode_can_error_frame(frame);
  EXPECT_EQ(report.state, hal::CanBusState::kErrorPassive);
  EXPECT_EQ(report.tx_error_count, 0x60);
  EXPECT_EQ(report.rx_error_count, 0x80);
}

}  // namespace
}  // namespace cambio::can
