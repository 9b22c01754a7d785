// The SDO client against CiA 301 §7.2.4.3's byte layouts (frames written out by hand here) and
// against the test's own SDO server (test_drive.hpp) over the in-process bus.
#include "cambio/canopen/sdo_client.hpp"

#include <gtest/gtest.h>

#include <array>
#include <string>
#include <vector>

#include "cambio/can/in_process_can_bus.hpp"
#include "cambio/canopen/sdo_transfer.hpp"
#include "cambio/hal/manual_clock.hpp"
#include "test_drive.hpp"

namespace cambio::canopen {
namespace {

using Bytes = std::vector<std::uint8_t>;

Bytes bytes_of(const hal::CanFrame& frame) {
  return Bytes(frame.data.begin(), frame.data.begin() + frame.length);
}

hal::CanFrame server_frame(int node, const Bytes& data) {
  hal::CanFrame frame;
  frame.id = 0x580u + static_cast<std::uint32_t>(node);
  frame.length = 8;
  for (std::size_t i = 0; i < data.size(); ++i) frame.data[i] = data[i];
  return frame;
}

TEST(SdoClient, ExpeditedDownloadOfFourBytesIsTheCia301Frame) {
  SdoClient client(5);
  const std::array<std::uint8_t, 4> value{0x78, 0x56, 0x34, 0x12};
  const hal::CanFrame request = client.start_download({0x607D, 2}, value, 0, 1000);
  EXPECT_EQ(request.id, 0x605u);
  EXPECT_EQ(bytes_of(request), (Bytes{0x23, 0x7D, 0x60, 0x02, 0x78, 0x56, 0x34, 0x12}));
  hal::CanFrame reply;
  EXPECT_FALSE(client.on_frame(server_frame(5, {0x60, 0x7D, 0x60, 0x02}), 0, reply));
  EXPECT_EQ(client.state(), SdoClient::State::kDone);
}

TEST(SdoClient, ExpeditedDownloadSizesOneAndTwoBytes) {
  SdoClient client(1);
  const std::array<std::uint8_t, 2> two{0xE8, 0x03};
  EXPECT_EQ(bytes_of(client.start_download({0x1017, 0}, two, 0, 1000)),
            (Bytes{0x2B, 0x17, 0x10, 0x00, 0xE8, 0x03, 0, 0}));
  const std::array<std::uint8_t, 1> one{0x08};
  EXPECT_EQ(bytes_of(client.start_download({0x6060, 0}, one, 0, 1000)),
            (Bytes{0x2F, 0x60, 0x60, 0x00, 0x08, 0, 0, 0}));
}

TEST(SdoClient, ExpeditedUploadWithSizeIndicated) {
  SdoClient client(3);
  EXPECT_EQ(bytes_of(client.start_upload({0x6041, 0}, 0, 1000)),
            (Bytes{0x40, 0x41, 0x60, 0x00, 0, 0, 0, 0}));
  hal::CanFrame reply;
  // scs 2, n = 2 (2 bytes unused), e = 1, s = 1: 0x4B.
  EXPECT_FALSE(
      client.on_frame(server_frame(3, {0x4B, 0x41, 0x60, 0x00, 0x37, 0x02, 0xAA, 0xAA}), 0, reply));
  EXPECT_EQ(client.state(), SdoClient::State::kDone);
  EXPECT_EQ(Bytes(client.data().begin(), client.data().end()), (Bytes{0x37, 0x02}));
}

TEST(SdoClient, SegmentedUploadOfAStringTogglesEachSegment) {
  SdoClient client(2);
  (void)client.start_upload({0x1008, 0}, 0, 1000);
  hal::CanFrame reply;
  // Initiate answer: scs 2, e = 0, s = 1 (0x41), size 10.
  ASSERT_TRUE(client.on_frame(server_frame(2, {0x41, 0x08, 0x10, 0x00, 10, 0, 0, 0}), 0, reply));
  EXPECT_EQ(bytes_of(reply), (Bytes{0x60, 0, 0, 0, 0, 0, 0, 0})) << "upload segment, toggle 0";
  // Segment 1: toggle 0, 7 bytes, not last: 0x00.
  ASSERT_TRUE(
      client.on_frame(server_frame(2, {0x00, 'C', 'a', 'm', 'b', 'i', 'o', ' '}), 0, reply));
  EXPECT_EQ(bytes_of(reply), (Bytes{0x70, 0, 0, 0, 0, 0, 0, 0})) << "upload segment, toggle 1";
  // Segment 2: toggle 1, n = 4 unused, last: 0x10 | 4 << 1 | 1 = 0x19.
  EXPECT_FALSE(client.on_frame(server_frame(2, {0x19, 'C', 'A', 'N', 0, 0, 0, 0}), 0, reply));
  EXPECT_EQ(client.state(), SdoClient::State::kDone);
  const std::string text(client.data().begin(), client.data().end());
  EXPECT_EQ(text, "Cambio CAN");
}

TEST(SdoClient, SegmentedDownloadSendsSizeThenToggledSegments) {
  SdoClient client(4);
  const std::string text = "0123456789";
  const std::span<const std::uint8_t> data(reinterpret_cast<const std::uint8_t*>(text.data()),
                                           text.size());
  EXPECT_EQ(bytes_of(client.start_download({0x2000, 1}, data, 0, 1000)),
            (Bytes{0x21, 0x00, 0x20, 0x01, 10, 0, 0, 0}));
  hal::CanFrame reply;
  ASSERT_TRUE(client.on_frame(server_frame(4, {0x60, 0x00, 0x20, 0x01}), 0, reply));
  EXPECT_EQ(bytes_of(reply), (Bytes{0x00, '0', '1', '2', '3', '4', '5', '6'}));
  ASSERT_TRUE(client.on_frame(server_frame(4, {0x20}), 0, reply));
  // Toggle 1, n = 4 unused, c = 1: 0x10 | 0x08 | 0x01.
  EXPECT_EQ(bytes_of(reply), (Bytes{0x19, '7', '8', '9', 0, 0, 0, 0}));
  EXPECT_FALSE(client.on_frame(server_frame(4, {0x30}), 0, reply));
  EXPECT_EQ(client.state(), SdoClient::State::kDone);
}

TEST(SdoClient, ServerAbortIsReportedWithItsCode) {
  SdoClient client(7);
  (void)client.start_upload({0x6502, 0}, 0, 1000);
  hal::CanFrame reply;
  EXPECT_FALSE(
      client.on_frame(server_frame(7, {0x80, 0x02, 0x65, 0x00, 0x00, 0x00, 0x02, 0x06}), 0, reply));
  EXPECT_EQ(client.state(), SdoClient::State::kAborted);
  EXPECT_EQ(client.failure(), SdoClient::Failure::kServerAbort);
  EXPECT_EQ(client.abort_code(), 0x0602'0000u);
}

TEST(SdoClient, WrongToggleIsAbortedWithTheToggleCode) {
  SdoClient client(2);
  (void)client.start_upload({0x1008, 0}, 0, 1000);
  hal::CanFrame reply;
  ASSERT_TRUE(client.on_frame(server_frame(2, {0x41, 0x08, 0x10, 0x00, 20, 0, 0, 0}), 0, reply));
  // The server answers with toggle 1 where 0 was asked.
  ASSERT_TRUE(client.on_frame(server_frame(2, {0x10, 1, 2, 3, 4, 5, 6, 7}), 0, reply));
  EXPECT_EQ(bytes_of(reply), (Bytes{0x80, 0x08, 0x10, 0x00, 0x00, 0x00, 0x03, 0x05}));
  EXPECT_EQ(client.state(), SdoClient::State::kAborted);
}

TEST(SdoClient, AnInitiateAnswerThatDoesNotFitTheRequestIsAborted) {
  hal::CanFrame reply;
  {
    // A download's answer that names another object: abort 0800 0000 (general error) for ours.
    SdoClient client(3);
    const std::array<std::uint8_t, 2> value{0x0F, 0x00};
    (void)client.start_download({0x6040, 0}, value, 0, 1000);
    ASSERT_TRUE(client.on_frame(server_frame(3, {0x60, 0x41, 0x60, 0x00}), 0, reply));
    EXPECT_EQ(bytes_of(reply), (Bytes{0x80, 0x40, 0x60, 0x00, 0x00, 0x00, 0x00, 0x08}));
    EXPECT_EQ(client.state(), SdoClient::State::kAborted);
  }
  {
    // An upload answered as a download (scs 3): abort 0504 0001 (invalid command specifier).
    SdoClient client(3);
    (void)client.start_upload({0x6041, 0}, 0, 1000);
    ASSERT_TRUE(client.on_frame(server_frame(3, {0x60, 0x41, 0x60, 0x00}), 0, reply));
    EXPECT_EQ(bytes_of(reply), (Bytes{0x80, 0x41, 0x60, 0x00, 0x01, 0x00, 0x04, 0x05}));
    EXPECT_EQ(client.state(), SdoClient::State::kAborted);
  }
}

TEST(SdoClient, TimeoutSendsTheTimeoutAbort) {
  SdoClient client(9);
  (void)client.start_upload({0x1000, 0}, 1'000, 500);
  hal::CanFrame reply;
  EXPECT_FALSE(client.poll(1'499, reply));
  ASSERT_TRUE(client.poll(1'500, reply));
  EXPECT_EQ(reply.id, 0x609u);
  EXPECT_EQ(bytes_of(reply), (Bytes{0x80, 0x00, 0x10, 0x00, 0x00, 0x00, 0x04, 0x05}));
  EXPECT_EQ(client.failure(), SdoClient::Failure::kTimeout);
}

TEST(SdoClient, FramesOfOtherNodesAreIgnored) {
  SdoClient client(2);
  (void)client.start_upload({0x1000, 0}, 0, 1000);
  hal::CanFrame reply;
  EXPECT_FALSE(client.on_frame(server_frame(3, {0x43, 0x00, 0x10, 0x00, 1, 2, 3, 4}), 0, reply));
  EXPECT_EQ(client.state(), SdoClient::State::kBusy);
}

struct Bench {
  hal::ManualClock clock;
  can::InProcessCanNetwork network{false, &clock};
  hal::CanBus& master = network.add_endpoint("master");
  testing::TestDrive drive{network.add_endpoint("drive"), 6};
  BusPump pump{master, clock, [this](hal::CanBus&, std::int64_t) {
                 drive.step();
                 clock.advance_to_ns(clock.now_ns() + 1'000'000);
               }};
};

TEST(SdoTransfer, SegmentedUploadFromTheTestServer) {
  Bench bench;
  const std::vector<std::uint8_t> name = sdo_upload(bench.pump, 6, {0x1008, 0}, 0.1);
  EXPECT_EQ(std::string(name.begin(), name.end()), "Test drive, a name longer than four bytes");
}

TEST(SdoTransfer, SegmentedDownloadToTheTestServer) {
  Bench bench;
  const std::string text = "a string of 23 bytes ok";
  sdo_download(bench.pump, 6, {0x2001, 0},
               std::span(reinterpret_cast<const std::uint8_t*>(text.data()), text.size()), 0.1);
  ASSERT_EQ(bench.drive.writes.size(), 1u);
  const std::vector<std::uint8_t> back = sdo_upload(bench.pump, 6, {0x2001, 0}, 0.1);
  EXPECT_EQ(std::string(back.begin(), back.end()), text);
}

TEST(SdoTransfer, AbortNamesNodeObjectAndMeaning) {
  Bench bench;
  try {
    (void)sdo_read_value(bench.pump, 6, {0x6502, 0}, 0.1);
    FAIL() << "expected an SdoError";
  } catch (const SdoError& error) {
    EXPECT_EQ(error.abort_code(), 0x0602'0000u);
    EXPECT_EQ(std::string(error.what()),
              "node 6: SDO upload of 0x6502:00 aborted by the drive: 0x06020000 (object does not "
              "exist in the object dictionary)");
  }
}

TEST(SdoTransfer, SilentNodeTimesOut) {
  Bench bench;
  bench.drive.answer_sdo = false;
  try {
    (void)sdo_read_value(bench.pump, 6, {0x1000, 0}, 0.05);
    FAIL() << "expected an SdoError";
  } catch (const SdoError& error) {
    EXPECT_EQ(error.abort_code(), 0x0504'0000u);
    EXPECT_NE(std::string(error.what()).find("node 6: SDO upload of 0x1000:00: no answer"),
              std::string::npos)
        << error.what();
  }
  // The client told the server it gave up: the last frame the drive saw is the timeout abort.
  bench.drive.step();
  ASSERT_FALSE(bench.drive.received.empty());
  EXPECT_EQ(bench.drive.received.back().data[0], 0x80);
}

}  // namespace
}  // namespace cambio::canopen
