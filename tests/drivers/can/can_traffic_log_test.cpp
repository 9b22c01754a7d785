// The --can-log writer: every frame sent and received through LoggingCanBus reaches the file in
// candump -L form, in order; records lost to a full ring are counted; write errors reported.
#include "cambio/can/can_traffic_log.hpp"

#include <fcntl.h>
#include <gtest/gtest.h>
#include <sys/stat.h>
#include <unistd.h>

#include <chrono>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "cambio/can/candump_log.hpp"
#include "cambio/can/in_process_can_bus.hpp"
#include "cambio/runtime/allocation_counter.hpp"

namespace cambio::can {
namespace {

namespace fs = std::filesystem;

// An endpoint of `network`, owned by it, handed to LoggingCanBus as if it were its own.
class BorrowedBus final : public hal::CanBus {
 public:
  explicit BorrowedBus(hal::CanBus& bus) : bus_(bus) {}
  const std::string& name() const override { return bus_.name(); }
  hal::Status send(const hal::CanFrame& f) override { return bus_.send(f); }
  hal::Status receive(hal::CanFrame& f) override { return bus_.receive(f); }
  hal::CanBusStatus status() const override { return bus_.status(); }

 private:
  hal::CanBus& bus_;
};

fs::path temp_path(const std::string& name) {
  return fs::temp_directory_path() / ("cambio_can_log_" + std::to_string(::getpid()) + "_" + name);
}

std::vector<std::string> read_lines(const fs::path& path) {
  std::ifstream in(path);
  std::vector<std::string> lines;
  for (std::string line; std::getline(in, line);) lines.push_back(line);
  return lines;
}

hal::CanFrame frame(std::uint32_t id, std::initializer_list<std::uint8_t> bytes) {
  hal::CanFrame f;
  f.id = id;
  for (std::uint8_t b : bytes) f.data[f.length++] = b;
  return f;
}

std::int64_t wall_us() {
  return std::chrono::duration_cast<std::chrono::microseconds>(
             std::chrono::system_clock::now().time_since_epoch())
      .count();
}

TEST(CanTrafficLog, RecordsSentAndReceivedFramesInOrder) {
  const fs::path path = temp_path("order.log");
  InProcessCanNetwork network(/*fd=*/true);
  hal::CanBus& peer = network.add_endpoint("peer");
  const std::int64_t before_us = wall_us();
  CanTrafficLog log(path.string(), 64, /*frame_stamps_on_monotonic=*/false);
  LoggingCanBus bus(std::make_unique<BorrowedBus>(network.add_endpoint("vcan0")), log);

  hal::CanFrame extended = frame(0x1234567, {0x01});
  extended.extended_id = true;
  hal::CanFrame fd = frame(0x7FF, {1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 12});
  fd.fd = true;
  fd.bit_rate_switch = true;
  ASSERT_EQ(bus.send(frame(0x123, {0xDE, 0xAD, 0xBE, 0xEF})), hal::Status::kOk);
  const std::vector<hal::CanFrame> batch{extended, fd};
  ASSERT_EQ(bus.send_batch(batch), 2u);
  ASSERT_EQ(peer.send(frame(0x581, {0x60, 0x00, 0x10})), hal::Status::kOk);
  hal::CanFrame received;
  ASSERT_EQ(bus.receive(received), hal::Status::kOk);
  EXPECT_EQ(bus.receive(received), hal::Status::kNoNewData);  // nothing logged for it
  hal::CanFrame too_long = frame(0x1, {});
  too_long.length = 9;
  EXPECT_EQ(bus.send(too_long), hal::Status::kRejected);  // refused frames are not logged

  const CanLogReport report = log.close();
  EXPECT_TRUE(report.ok()) << report.error;
  EXPECT_EQ(report.records_written, 4u);
  const std::int64_t after_us = wall_us();

  const std::vector<std::string> lines = read_lines(path);
  ASSERT_EQ(lines.size(), 4u);
  const char* const frames[] = {"123#DEADBEEF", "01234567#01", "7FF##50102030405060708090A0B0C",
                                "581#600010"};
  std::int64_t previous_us = before_us;
  for (std::size_t i = 0; i < lines.size(); ++i) {
    const CandumpRecord record = parse_candump_line(lines[i]);
    EXPECT_EQ(record.interface, "vcan0");
    EXPECT_EQ(format_candump_frame(record.frame), frames[i]);
    EXPECT_GE(record.wall_time_us, previous_us);
    EXPECT_LE(record.wall_time_us, after_us);
    previous_us = record.wall_time_us;
  }
  fs::remove(path);
}

TEST(CanTrafficLog, LoggingNeverAllocatesOnTheLoopSide) {
  const fs::path path = temp_path("alloc.log");
  InProcessCanNetwork network;
  hal::CanBus& peer = network.add_endpoint("peer");
  CanTrafficLog log(path.string(), 4096);
  LoggingCanBus bus(std::make_unique<BorrowedBus>(network.add_endpoint("can0")), log);
  const hal::CanFrame f = frame(0x201, {1, 2, 3, 4});
  const std::uint64_t counter_check = runtime::thread_allocation_count();
  (void)peer.send_batch(std::vector<hal::CanFrame>(1, f));  // escapes: cannot be elided
  ASSERT_GT(runtime::thread_allocation_count(), counter_check) << "allocations are not counted";
  const std::uint64_t before = runtime::thread_allocation_count();
  hal::CanFrame in;
  for (int i = 0; i < 1000; ++i) {
    (void)bus.send(f);
    (void)peer.send(f);
    (void)bus.receive(in);
  }
  EXPECT_EQ(runtime::thread_allocation_count() - before, 0u);
  EXPECT_EQ(log.close().records_written + log.records_dropped(), 2000u);
  fs::remove(path);
}

TEST(CanTrafficLog, CountsRecordsDroppedWhileTheWriterIsStuck) {
  // The log is a fifo nobody reads: the writer blocks once the pipe is full, the ring fills,
  // and every further record is dropped and counted. Then reading the fifo lets close() finish.
  const fs::path path = temp_path("stuck.fifo");
  ASSERT_EQ(::mkfifo(path.c_str(), 0600), 0);
  const int reader = ::open(path.c_str(), O_RDONLY | O_NONBLOCK);
  ASSERT_GE(reader, 0);
  InProcessCanNetwork network;
  {
    CanTrafficLog log(path.string(), 16);
    LoggingCanBus bus(std::make_unique<BorrowedBus>(network.add_endpoint("can0")), log);
    constexpr int kFrames = 200'000;  // ~5 MB of lines against a 64 KiB pipe and 16 records
    for (int i = 0; i < kFrames; ++i) (void)bus.send(frame(0x100, {1, 2, 3, 4, 5, 6, 7, 8}));
    EXPECT_GT(log.records_dropped(), 0u);

    // Drain the fifo on this thread until close() (on another) has finished writing.
    std::uint64_t lines = 0;
    CanLogReport report;
    std::thread closer([&] { report = log.close(); });
    ::fcntl(reader, F_SETFL, 0);  // blocking reads: EOF when the writer closes its end
    char buffer[65536];
    for (ssize_t n; (n = ::read(reader, buffer, sizeof(buffer))) > 0;) {
      for (ssize_t i = 0; i < n; ++i) lines += buffer[i] == '\n';
    }
    closer.join();
    EXPECT_TRUE(report.error.empty()) << report.error;
    EXPECT_GT(report.records_dropped, 0u);
    EXPECT_EQ(report.records_written, lines);
    EXPECT_EQ(report.records_written + report.records_dropped, static_cast<std::uint64_t>(kFrames));
    EXPECT_FALSE(report.ok());
  }
  ::close(reader);
  fs::remove(path);
}

TEST(CanTrafficLog, ReportsAFailedWriteNamingTheFile) {
  InProcessCanNetwork network;
  CanTrafficLog log("/dev/full", 64);
  LoggingCanBus bus(std::make_unique<BorrowedBus>(network.add_endpoint("can0")), log);
  ASSERT_EQ(bus.send(frame(0x80, {})), hal::Status::kOk);
  const CanLogReport report = log.close();
  EXPECT_NE(report.error.find("/dev/full"), std::string::npos) << report.error;
  EXPECT_NE(report.error.find("No space left on device"), std::string::npos) << report.error;
  EXPECT_FALSE(report.ok());
}

TEST(CanTrafficLog, AnEarlierLogStaysWholeUntilTheNewOneIsClosedAndARunThatNeverStartedKeepsIt) {
  const fs::path path = temp_path("earlier.log");
  const fs::path incomplete = path.string() + ".incomplete";
  fs::remove(incomplete);
  { std::ofstream(path) << "(1.000000) can0 080#\n"; }
  InProcessCanNetwork network;
  {
    CanTrafficLog log(path.string(), 64);
    LoggingCanBus bus(std::make_unique<BorrowedBus>(network.add_endpoint("can0")), log);
    ASSERT_EQ(bus.send(frame(0x123, {0xAB})), hal::Status::kOk);
    EXPECT_EQ(read_lines(path).size(), 1u) << "the earlier log is untouched while running";
    const CanLogReport report = log.abandon();  // The run never started.
    EXPECT_EQ(report.abandoned_path, incomplete.string());
  }
  ASSERT_EQ(read_lines(path).size(), 1u);
  EXPECT_NE(read_lines(path)[0].find("080#"), std::string::npos) << "the earlier log is whole";
  ASSERT_EQ(read_lines(incomplete).size(), 1u);
  EXPECT_NE(read_lines(incomplete)[0].find("123#AB"), std::string::npos);
  {
    CanTrafficLog log(path.string(), 64);
    LoggingCanBus bus(std::make_unique<BorrowedBus>(network.add_endpoint("can1")), log);
    ASSERT_EQ(bus.send(frame(0x124, {0xCD})), hal::Status::kOk);
    EXPECT_TRUE(log.close().ok());
  }
  ASSERT_EQ(read_lines(path).size(), 1u);
  EXPECT_NE(read_lines(path)[0].find("124#CD"), std::string::npos) << "closed: put in place";
  for (const auto& entry : fs::directory_iterator(path.parent_path())) {
    EXPECT_EQ(entry.path().string().find(path.string() + ".cambio-partial"), std::string::npos)
        << "no staging file is left behind";
  }
  fs::remove(path);
  fs::remove(incomplete);
}

TEST(CanTrafficLog, RefusesAFileItCannotCreate) {
  try {
    CanTrafficLog log("/nonexistent-dir/can.log");
    FAIL() << "opened";
  } catch (const std::runtime_error& error) {
    EXPECT_NE(std::string(error.what()).find("/nonexistent-dir/can.log"), std::string::npos);
  }
}

}  // namespace
}  // namespace cambio::can
