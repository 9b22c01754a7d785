// The emulated drive's SDO server against raw CiA 301 SDO frames built here.
#include <string>

#include "drive_test_support.hpp"

namespace cambio::virtual_rig::test {
namespace {

TEST(SdoServer, ExpeditedUploadCarriesTheValueAndItsSize) {
  DriveBench bench;
  bench.power_on();
  // 0x1000 device type: 4 bytes, scs 2, e = s = 1, n = 0 -> 0x43.
  const auto r = bench.sdo({0x40, 0x00, 0x10, 0x00, 0, 0, 0, 0});
  EXPECT_EQ(r.id, 0x583u);
  EXPECT_EQ(r.length, 8);
  EXPECT_EQ(r.data[0], 0x43);
  EXPECT_EQ(le_i32(r, 4), 0x00020192);
  // 0x1001 error register: 1 byte, n = 3 -> 0x4F.
  EXPECT_EQ(bench.upload(0x1001, 0).command, 0x4F);
  // 0x6041 statusword: 2 bytes, n = 2 -> 0x4B; switch on disabled after boot (0x0040, remote).
  const SdoReply status = bench.upload(0x6041, 0);
  EXPECT_EQ(status.command, 0x4B);
  EXPECT_EQ(status.value & 0x4F, 0x40u);
}

TEST(SdoServer, SegmentedUploadOfTheDeviceName) {
  DriveBench bench;
  bench.power_on();
  const std::string expected = "Cambio virtual CiA 402 drive";
  const auto initiate = bench.sdo({0x40, 0x08, 0x10, 0x00, 0, 0, 0, 0});
  // scs 2, e = 0, s = 1: the size in bytes 4..7.
  ASSERT_EQ(initiate.data[0], 0x41);
  ASSERT_EQ(static_cast<std::size_t>(le_i32(initiate, 4)), expected.size());
  std::string text;
  std::uint8_t toggle = 0;
  for (int segment = 0; segment < 10; ++segment) {
    const auto r = bench.sdo({static_cast<std::uint8_t>(0x60 | toggle << 4), 0, 0, 0, 0, 0, 0, 0});
    ASSERT_EQ(r.data[0] >> 5, 0) << "scs 0: upload segment";
    ASSERT_EQ((r.data[0] >> 4) & 1, toggle) << "the server echoes the toggle bit";
    const int bytes = 7 - ((r.data[0] >> 1) & 7);
    text.append(reinterpret_cast<const char*>(&r.data[1]), static_cast<std::size_t>(bytes));
    toggle ^= 1;
    if (r.data[0] & 1) break;
  }
  EXPECT_EQ(text, expected);
}

TEST(SdoServer, UploadSegmentWithTheWrongToggleIsAborted) {
  DriveBench bench;
  bench.power_on();
  ASSERT_EQ(bench.sdo({0x40, 0x08, 0x10, 0x00, 0, 0, 0, 0}).data[0], 0x41);
  const auto first = bench.sdo({0x60, 0, 0, 0, 0, 0, 0, 0});
  EXPECT_EQ(first.data[0] >> 5, 0);
  const auto repeated = bench.sdo({0x60, 0, 0, 0, 0, 0, 0, 0});  // Toggle should be 1 now.
  EXPECT_EQ(repeated.data[0], 0x80);
  EXPECT_EQ(static_cast<std::uint32_t>(le_i32(repeated, 4)), 0x05030000u);
  // The transfer is over: a further segment request is out of place.
  const auto after = bench.sdo({0x70, 0, 0, 0, 0, 0, 0, 0});
  EXPECT_EQ(static_cast<std::uint32_t>(le_i32(after, 4)), 0x05040001u);
}

TEST(SdoServer, ExpeditedDownloadIsStoredAndReadBack) {
  DriveBench bench;
  bench.power_on();
  EXPECT_EQ(bench.write(0x6065, 0, 12345, 4), 0u);
  EXPECT_EQ(bench.upload(0x6065, 0).value, 12345u);
  // Without size indication (0x22) the data is as long as the object (UNSIGNED16 here).
  const auto r = bench.sdo({0x22, 0x17, 0x10, 0x00, 0xC8, 0x00, 0xAA, 0xBB});
  EXPECT_EQ(r.data[0], 0x60);
  EXPECT_EQ(bench.upload(0x1017, 0).value, 200u);
}

TEST(SdoServer, SegmentedDownload) {
  DriveBench bench;
  bench.power_on();
  // Initiate: ccs 1, e = 0, s = 1, size 4.
  const auto initiate = bench.sdo({0x21, 0x65, 0x60, 0x00, 4, 0, 0, 0});
  EXPECT_EQ(initiate.data[0], 0x60);
  // One segment: toggle 0, n = 3 (4 of 7 bytes used), c = 1.
  const auto segment = bench.sdo({0x00 | 3 << 1 | 1, 0x10, 0x27, 0x00, 0x00, 0, 0, 0});
  EXPECT_EQ(segment.data[0], 0x20) << "scs 1, toggle 0";
  EXPECT_EQ(bench.upload(0x6065, 0).value, 10000u);
}

TEST(SdoServer, SegmentedDownloadWithTheWrongToggleIsAborted) {
  DriveBench bench;
  bench.power_on();
  EXPECT_EQ(bench.sdo({0x21, 0x65, 0x60, 0x00, 8, 0, 0, 0}).data[0], 0x60);
  const auto r = bench.sdo({0x10, 1, 2, 3, 4, 5, 6, 7});  // Toggle 1 on the first segment.
  EXPECT_EQ(r.data[0], 0x80);
  EXPECT_EQ(static_cast<std::uint32_t>(le_i32(r, 4)), 0x05030000u);
}

TEST(SdoServer, AbortsWithTheCodeCiA301Names) {
  DriveBench bench;
  bench.power_on();
  EXPECT_EQ(bench.upload(0x1234, 0).value, 0x06020000u) << "object does not exist";
  EXPECT_EQ(bench.upload(0x1018, 7).value, 0x06090011u) << "subindex does not exist";
  EXPECT_EQ(bench.write(0x6041, 0, 0, 2), 0x06010002u) << "read only";
  EXPECT_EQ(bench.write(0x1000, 0, 0, 4), 0x06010002u) << "read only";
  EXPECT_EQ(bench.write(0x1008, 0, 0, 4), 0x06010002u) << "const string";
  EXPECT_EQ(bench.write(0x6065, 0, 7, 2), 0x06070013u) << "length too low";
  EXPECT_EQ(bench.write(0x6060, 0, 8, 2), 0x06070012u) << "length too high";
  EXPECT_EQ(bench.write(0x6060, 0, 5, 1), 0x06090030u) << "a mode the drive does not have";
  EXPECT_EQ(bench.write(0x1600, 0, 9, 1), 0x06090031u) << "more than 8 mapped objects";
  EXPECT_EQ(bench.write(0x60C2, 2, 64, 1), 0x06090031u) << "interpolation index above 63";
  const auto block = bench.sdo({0xA0, 0x00, 0x10, 0x00, 0, 0, 0, 0});  // ccs 5: block upload.
  EXPECT_EQ(static_cast<std::uint32_t>(le_i32(block, 4)), 0x05040001u);
  const auto unknown = bench.sdo({0xE0, 0x00, 0x10, 0x00, 0, 0, 0, 0});  // ccs 7.
  EXPECT_EQ(static_cast<std::uint32_t>(le_i32(unknown, 4)), 0x05040001u);
  const auto stray = bench.sdo({0x00, 1, 2, 3, 4, 5, 6, 7});  // A segment with no transfer.
  EXPECT_EQ(static_cast<std::uint32_t>(le_i32(stray, 4)), 0x05040001u);
  // The abort names the object it concerns.
  const auto r = bench.sdo({0x40, 0x34, 0x12, 0x05, 0, 0, 0, 0});
  EXPECT_EQ(r.data[1], 0x34);
  EXPECT_EQ(r.data[2], 0x12);
  EXPECT_EQ(r.data[3], 0x05);
}

TEST(SdoServer, MalformedRequestsAreCountedAndIgnored) {
  DriveBench bench;
  bench.power_on();
  const auto replies = bench.exchange({frame(0x603, {0x40, 0x00, 0x10})});
  EXPECT_TRUE(with_id(replies, 0x583).empty());
  EXPECT_EQ(bench.drive().counters().malformed_frames, 1u);
  // Requests for another node are not this drive's business.
  EXPECT_TRUE(bench.exchange({frame(0x604, {0x40, 0x00, 0x10, 0, 0, 0, 0, 0})}).empty());
}

TEST(SdoServer, NoSdoWhileStopped) {
  DriveBench bench;
  bench.power_on();
  bench.nmt(0x02);
  EXPECT_TRUE(bench.exchange({frame(0x603, {0x40, 0x00, 0x10, 0, 0, 0, 0, 0})}).empty());
  bench.nmt(0x80);
  EXPECT_EQ(bench.upload(0x1000, 0).value, 0x00020192u);
}

}  // namespace
}  // namespace cambio::virtual_rig::test
