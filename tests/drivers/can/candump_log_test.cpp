// candump -L lines: parsed as can-utils' lib.c parses them (the examples of its lib.h and of
// cansend's help), formatted as candump prints them (lines recorded from candump 2020.11 on
// Linux 6.1, where received CAN FD frames carry CANFD_FDF).
#include "cambio/can/candump_log.hpp"

#include <gtest/gtest.h>

#include <vector>

namespace cambio::can {
namespace {

std::vector<std::uint8_t> bytes_of(const hal::CanFrame& frame) {
  return {frame.data.begin(), frame.data.begin() + (frame.remote_request ? 0 : frame.length)};
}

TEST(CandumpLog, ParsesTheLibHExamples) {
  hal::CanFrame f = parse_candump_frame("123#");
  EXPECT_EQ(f.id, 0x123u);
  EXPECT_FALSE(f.extended_id);
  EXPECT_EQ(f.length, 0);

  f = parse_candump_frame("12345678#");
  EXPECT_EQ(f.id, 0x12345678u);
  EXPECT_TRUE(f.extended_id);

  f = parse_candump_frame("123#R");
  EXPECT_TRUE(f.remote_request);
  EXPECT_EQ(f.length, 0);
  f = parse_candump_frame("7A1#r");
  EXPECT_EQ(f.id, 0x7A1u);
  EXPECT_TRUE(f.remote_request);
  f = parse_candump_frame("00000123#R3");
  EXPECT_TRUE(f.extended_id);
  EXPECT_TRUE(f.remote_request);
  EXPECT_EQ(f.length, 3);

  f = parse_candump_frame("123#00");
  EXPECT_EQ(bytes_of(f), std::vector<std::uint8_t>{0x00});
  const std::vector<std::uint8_t> eight{0x11, 0x22, 0x33, 0x44, 0x55, 0x66, 0x77, 0x88};
  EXPECT_EQ(bytes_of(parse_candump_frame("123#1122334455667788")), eight);
  EXPECT_EQ(bytes_of(parse_candump_frame("123#11.22.33.44.55.66.77.88")), eight);
  EXPECT_EQ(bytes_of(parse_candump_frame("123#11.2233.44556677.88")), eight);

  f = parse_candump_frame("32345678#112233");  // CAN_ERR_FLAG (0x20000000) set
  EXPECT_TRUE(f.error_frame);
  EXPECT_FALSE(f.extended_id);
  EXPECT_EQ(f.id, 0x12345678u);
  EXPECT_EQ(bytes_of(f), (std::vector<std::uint8_t>{0x11, 0x22, 0x33}));

  f = parse_candump_frame("123##0112233");
  EXPECT_TRUE(f.fd);
  EXPECT_FALSE(f.bit_rate_switch);
  EXPECT_EQ(bytes_of(f), (std::vector<std::uint8_t>{0x11, 0x22, 0x33}));
  f = parse_candump_frame("123##1112233");
  EXPECT_TRUE(f.bit_rate_switch);
  EXPECT_FALSE(f.error_state_indicator);
  f = parse_candump_frame("123##2112233");
  EXPECT_FALSE(f.bit_rate_switch);
  EXPECT_TRUE(f.error_state_indicator);
  f = parse_candump_frame("123##3");
  EXPECT_TRUE(f.fd && f.bit_rate_switch && f.error_state_indicator);
  EXPECT_EQ(f.length, 0);

  f = parse_candump_frame("213##311223344");
  EXPECT_EQ(f.id, 0x213u);
  EXPECT_EQ(f.length, 4);
  f = parse_candump_frame("1F334455#1122334455667788");
  EXPECT_EQ(f.id, 0x1F334455u);
  EXPECT_EQ(bytes_of(f), eight);
}

TEST(CandumpLog, LinesRoundTripAsCandumpPrintsThem) {
  const char* const lines[] = {
      "(1436509052.249713) vcan0 123#DEADBEEF",  // can-utils' README
      "(1795380747.267521) vcan0 123#DEADBEEF",
      "(1795380747.334280) vcan0 12345678#112233",
      "(1795380747.389867) vcan0 123#R",
      "(1795380747.429932) vcan0 123#R3",
      "(1795380747.492662) vcan0 12345678#R",
      "(1795380747.548946) vcan0 123#",
      "(1795380747.596528) vcan0 123##5112233",
      "(1795380747.654250) vcan0 123##7",
      "(1795380747.703396) vcan0 123##4",
      "(1795380747.764674) vcan0 7FF##6",
      "(1795380747.858578) vcan0 123#1122334455667788",
      "(1795380747.936517) vcan0 123##4112233445566778899000000",
      "(0000000001.000001) can0 20000040#0000000000000000",
  };
  for (const char* line : lines) {
    const CandumpRecord record = parse_candump_line(line);
    EXPECT_EQ(format_candump_line(record.wall_time_us, record.interface, record.frame), line);
  }
  const CandumpRecord record = parse_candump_line("(1436509052.249713) vcan0 123#DEADBEEF\n");
  EXPECT_EQ(record.wall_time_us, 1436509052249713);
  EXPECT_EQ(record.interface, "vcan0");
  EXPECT_EQ(bytes_of(record.frame), (std::vector<std::uint8_t>{0xDE, 0xAD, 0xBE, 0xEF}));
}

TEST(CandumpLog, FormatsFramesTheWayLibCDoes) {
  hal::CanFrame frame;
  frame.id = 0x7;
  frame.length = 2;
  frame.data[0] = 0xab;
  frame.data[1] = 0x01;
  EXPECT_EQ(format_candump_frame(frame), "007#AB01");  // 3 upper-case digits, zero-padded
  frame.extended_id = true;
  EXPECT_EQ(format_candump_frame(frame), "00000007#AB01");
  frame.extended_id = false;
  frame.fd = true;
  frame.bit_rate_switch = true;
  EXPECT_EQ(format_candump_frame(frame), "007##5AB01");  // FDF | BRS
  // Doc lines without CANFD_FDF are read, and written back as candump prints them today.
  EXPECT_EQ(format_candump_frame(parse_candump_frame("123##1112233")), "123##5112233");
  EXPECT_EQ(format_candump_line(5'000'042, "can1", parse_candump_frame("5AA#")),
            "(0000000005.000042) can1 5AA#");
}

TEST(CandumpLog, ReadsLinesPaddedForSeveralInterfaces) {
  // candump -L vcan0 can1ab prints each name right-aligned to the longest.
  const CandumpRecord record = parse_candump_line("(1436509052.249713)  vcan0 123#01");
  EXPECT_EQ(record.interface, "vcan0");
  EXPECT_EQ(record.frame.length, 1);
}

void expect_error(const std::string& line, const std::string& fragment) {
  try {
    (void)parse_candump_line(line);
    ADD_FAILURE() << "accepted: " << line;
  } catch (const CandumpParseError& error) {
    EXPECT_NE(std::string(error.what()).find(fragment), std::string::npos)
        << line << " -> " << error.what();
  }
}

TEST(CandumpLog, RefusesWhatLibCWouldNotPrintNamingTheColumn) {
  expect_error("(1436509052.249713) vcan0 12#00", "column 27: expected a CAN id of 3");
  expect_error("(1436509052.249713) vcan0 1G3#00", "column 28: expected a hex digit");
  expect_error("(1436509052.249713) vcan0 800#", "standard CAN id above 7FF");
  expect_error("(1436509052.249713) vcan0 123#0", "column 31: expected two hex digits");
  expect_error("(1436509052.249713) vcan0 123#112233445566778899", "more than 8 data bytes");
  expect_error("(1436509052.249713) vcan0 123##0112233445566778899",
               "9 data bytes is not a CAN FD length");
  expect_error("(1436509052.2497) vcan0 123#", "expected 6 digits of microseconds");
  expect_error("1436509052.249713 vcan0 123#", "column 1: expected '('");
  expect_error("(1436509052.249713) vcan0", "expected a space");
  expect_error("(1436509052.249713) vcan0 123#R9", "expected nothing or a DLC 0-8");
  expect_error("(1436509052.249713) vcan0 123#00 T", "unexpected text after the frame");
  expect_error("(1436509052.249713) vcan0 A0000000#00", "error frame id with flags");
}

}  // namespace
}  // namespace cambio::can
