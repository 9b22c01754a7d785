// SocketCanBus and the candump -L log against the real Linux CAN stack, with can-utils as an
// independent peer. Runs where PF_CAN and vcan0 (CAN FD, mtu 72) / vcan1 (classic, mtu 16)
// exist: the QEMU guest of tests/can_vm/run_in_guest.sh (ctest label can_vm); skips elsewhere.
// Needs root for `ip`/`tc` (the guest runs as root).
#include <gtest/gtest.h>
#include <linux/can.h>
#include <linux/can/error.h>
#include <net/if.h>
#include <sys/socket.h>
#include <unistd.h>

#include <chrono>
#include <csignal>
#include <cstdlib>
#include <ctime>
#include <filesystem>
#include <fstream>
#include <string>
#include <thread>
#include <vector>

#include "cambio/can/can_bitrate.hpp"
#include "cambio/can/can_traffic_log.hpp"
#include "cambio/can/candump_log.hpp"
#include "cambio/can/socketcan_bus.hpp"
#include "cambio/runtime/allocation_counter.hpp"

namespace cambio::can {
namespace {

namespace fs = std::filesystem;
constexpr std::int64_t kSecond_ns = 1'000'000'000;

bool have_vcan() {
  const int fd = ::socket(PF_CAN, SOCK_RAW, CAN_RAW);
  if (fd < 0) return false;
  ::close(fd);
  return ::if_nametoindex("vcan0") != 0 && ::if_nametoindex("vcan1") != 0;
}

class SocketCanVm : public ::testing::Test {
 protected:
  void SetUp() override {
    if (!have_vcan()) {
      GTEST_SKIP() << "no PF_CAN or no vcan0/vcan1 here; run through tests/can_vm/run_in_guest.sh";
    }
  }
};

std::int64_t monotonic_ns() {
  timespec ts{};
  clock_gettime(CLOCK_MONOTONIC, &ts);
  return std::int64_t{ts.tv_sec} * kSecond_ns + ts.tv_nsec;
}

std::unique_ptr<SocketCanBus> open_bus(const std::string& interface, bool fd = false,
                                       std::vector<CanFilter> filters = {}) {
  return SocketCanBus::open(
      {.interface = interface, .fd = fd, .filters = std::move(filters), .batch_size = 16});
}

hal::CanFrame frame(std::uint32_t id, std::initializer_list<std::uint8_t> bytes) {
  hal::CanFrame f;
  f.id = id;
  for (std::uint8_t b : bytes) f.data[f.length++] = b;
  return f;
}

// Waits (up to 10 s: the guest is emulated) for the next frame; data frames only unless asked.
bool next_frame(hal::CanBus& bus, hal::CanFrame& out, bool error_frames_too = false) {
  const std::int64_t give_up_ns = monotonic_ns() + 10 * kSecond_ns;
  while (monotonic_ns() < give_up_ns) {
    if (bus.receive(out) == hal::Status::kOk) {
      if (error_frames_too || !out.error_frame) return true;
      continue;
    }
    (void)bus.wait_for_frame(100'000'000);
  }
  return false;
}

void expect_same_frame(const hal::CanFrame& a, const hal::CanFrame& b) {
  EXPECT_EQ(format_candump_frame(a), format_candump_frame(b));
  EXPECT_EQ(a.id, b.id);
  EXPECT_EQ(a.extended_id, b.extended_id);
  EXPECT_EQ(a.remote_request, b.remote_request);
  EXPECT_EQ(a.fd, b.fd);
  EXPECT_EQ(a.bit_rate_switch, b.bit_rate_switch);
  EXPECT_EQ(a.length, b.length);
}

int shell(const std::string& command) {
  const int status = std::system(command.c_str());
  return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

std::vector<std::string> read_lines(const fs::path& path) {
  std::ifstream in(path);
  std::vector<std::string> lines;
  for (std::string line; std::getline(in, line);) lines.push_back(line);
  return lines;
}

fs::path temp_file(const std::string& name) {
  return fs::temp_directory_path() / ("cambio_vm_" + std::to_string(::getpid()) + "_" + name);
}

TEST_F(SocketCanVm, FramesRoundTripBetweenTwoBusesWithPlausibleStamps) {
  auto a = open_bus("vcan0");
  auto b = open_bus("vcan0");
  EXPECT_EQ(a->interface_mtu(), CANFD_MTU);
  hal::CanFrame extended = frame(0x1ABCDEF0, {0xCA, 0xFE});
  extended.extended_id = true;
  hal::CanFrame remote = frame(0x701, {});
  remote.remote_request = true;
  remote.length = 1;
  const std::vector<hal::CanFrame> sent{frame(0x123, {1, 2, 3, 4, 5, 6, 7, 8}), extended, remote,
                                        frame(0x000, {})};
  const std::int64_t before_ns = monotonic_ns();
  for (const auto& f : sent) ASSERT_EQ(a->send(f), hal::Status::kOk);
  for (const auto& f : sent) {
    hal::CanFrame got;
    ASSERT_TRUE(next_frame(*b, got));
    expect_same_frame(got, f);
    EXPECT_GE(got.stamp_ns, before_ns - 1'000'000);  // offset sampling error, well under 1 ms
    EXPECT_LE(got.stamp_ns, monotonic_ns() + 1'000'000);
  }
  // Our own frames do not come back to us (CAN_RAW_RECV_OWN_MSGS is off).
  hal::CanFrame none;
  EXPECT_EQ(a->receive(none), hal::Status::kNoNewData);

  // A batch of 100 in one go arrives whole and in order through the recvmmsg ring.
  std::vector<hal::CanFrame> batch;
  for (std::uint32_t i = 0; i < 100; ++i)
    batch.push_back(frame(0x200 + i, {static_cast<std::uint8_t>(i)}));
  EXPECT_EQ(a->send_batch(batch), batch.size());
  for (const auto& f : batch) {
    hal::CanFrame got;
    ASSERT_TRUE(next_frame(*b, got));
    expect_same_frame(got, f);
  }
  EXPECT_EQ(a->status().frames_sent, sent.size() + batch.size());
  EXPECT_EQ(b->status().frames_received, sent.size() + batch.size());
  EXPECT_EQ(b->status().state, hal::CanBusState::kErrorActive);
}

TEST_F(SocketCanVm, SendAndReceiveNeverAllocate) {
  auto a = open_bus("vcan0");
  auto b = open_bus("vcan0");
  const hal::CanFrame f = frame(0x181, {1, 2});
  std::vector<hal::CanFrame> batch(8, f);
  hal::CanFrame got;
  const std::uint64_t counter_check = runtime::thread_allocation_count();
  (void)a->send_batch(std::vector<hal::CanFrame>(1, f));  // escapes: cannot be elided
  ASSERT_GT(runtime::thread_allocation_count(), counter_check) << "allocations are not counted";
  const std::uint64_t before = runtime::thread_allocation_count();
  for (int i = 0; i < 200; ++i) {
    (void)a->send(f);
    (void)a->send_batch(batch);
    while (b->receive(got) == hal::Status::kOk) {
    }
  }
  (void)b->wait_for_frame(0);
  (void)b->status();
  EXPECT_EQ(runtime::thread_allocation_count() - before, 0u);
}

TEST_F(SocketCanVm, CansendFrameIsReceivedWithItsBytesAndAKernelStamp) {
  auto bus = open_bus("vcan0");
  const std::int64_t before_ns = monotonic_ns();
  ASSERT_EQ(shell("cansend vcan0 123#DEADBEEF"), 0);
  const std::int64_t after_ns = monotonic_ns();
  hal::CanFrame got;
  ASSERT_TRUE(next_frame(*bus, got));
  EXPECT_EQ(format_candump_frame(got), "123#DEADBEEF");
  EXPECT_EQ(got.data[0], 0xDE);
  EXPECT_EQ(got.data[3], 0xEF);
  // Stamped when the kernel received it, while cansend ran: not when we read it.
  EXPECT_GE(got.stamp_ns, before_ns - 1'000'000);
  EXPECT_LE(got.stamp_ns, after_ns + 1'000'000);
}

// candump -L in the background, started and known to be listening (it has printed a marker
// frame we keep sending until it shows), stopped on destruction.
class Candump {
 public:
  explicit Candump(const std::string& interface, hal::CanBus& sender)
      : path_(temp_file("candump.log")) {
    const fs::path pid = temp_file("candump.pid");
    EXPECT_EQ(shell("candump -L " + interface + " >" + path_.string() + " 2>&1 & echo $! >" +
                    pid.string()),
              0);
    std::ifstream(pid) >> pid_;
    fs::remove(pid);
    wait_for_marker(sender);
  }
  ~Candump() {
    if (pid_ > 0) ::kill(pid_, SIGTERM);
    fs::remove(path_);
  }
  // Sends the marker until candump prints it; returns the lines seen before it, dropping markers.
  std::vector<std::string> wait_for_marker(hal::CanBus& sender) {
    hal::CanFrame marker = frame(0x7FE, {0xAA, static_cast<std::uint8_t>(markers_++)});
    const std::string marker_text = format_candump_frame(marker);
    for (int attempt = 0; attempt < 200; ++attempt) {
      (void)sender.send(marker);
      std::this_thread::sleep_for(std::chrono::milliseconds(50));
      std::vector<std::string> lines = read_lines(path_);
      for (std::size_t i = 0; i < lines.size(); ++i) {
        if (lines[i].ends_with(marker_text)) {
          std::vector<std::string> before;
          for (std::size_t j = seen_; j < i; ++j) {
            if (lines[j].find(" 7FE#AA") == std::string::npos) before.push_back(lines[j]);
          }
          seen_ = lines.size();
          return before;
        }
      }
    }
    ADD_FAILURE() << "candump never printed " << marker_text;
    return {};
  }

 private:
  fs::path path_;
  pid_t pid_ = 0;
  int markers_ = 0;
  std::size_t seen_ = 0;
};

TEST_F(SocketCanVm, CandumpPrintsOurFramesAsOurFormatterDoes) {
  auto bus = open_bus("vcan0", /*fd=*/true);
  auto listener = open_bus("vcan0", /*fd=*/true);
  Candump candump("vcan0", *bus);
  hal::CanFrame drained;
  while (listener->receive(drained) == hal::Status::kOk) {
  }
  hal::CanFrame extended = frame(0x00000123, {0x11, 0x22, 0x33});
  extended.extended_id = true;
  hal::CanFrame remote = frame(0x123, {});
  remote.remote_request = true;
  remote.length = 3;
  hal::CanFrame fd = frame(0x7FF, {});
  fd.fd = true;
  fd.bit_rate_switch = true;
  fd.length = 64;
  for (std::uint8_t i = 0; i < 64; ++i) fd.data[i] = i;
  hal::CanFrame fd_esi = frame(0x100, {0xDE, 0xAD, 0xBE, 0xEF, 0, 0, 0, 0, 1, 2, 3, 4});
  fd_esi.fd = true;
  fd_esi.error_state_indicator = true;
  const std::vector<hal::CanFrame> frames{
      frame(0x123, {0xDE, 0xAD, 0xBE, 0xEF}), extended, remote, fd, fd_esi, frame(0x080, {})};
  for (const auto& f : frames) ASSERT_EQ(bus->send(f), hal::Status::kOk);
  const std::vector<std::string> lines = candump.wait_for_marker(*bus);
  ASSERT_EQ(lines.size(), frames.size());
  for (std::size_t i = 0; i < frames.size(); ++i) {
    const CandumpRecord record = parse_candump_line(lines[i]);
    EXPECT_EQ(record.interface, "vcan0");
    EXPECT_EQ(format_candump_frame(record.frame), format_candump_frame(frames[i])) << lines[i];
    // Our receiving socket got the same kernel stamp candump printed (to the microsecond),
    // modulo our CLOCK_REALTIME -> CLOCK_MONOTONIC offset estimate.
    hal::CanFrame got;
    ASSERT_TRUE(next_frame(*listener, got));
    while (got.id == 0x7FE) ASSERT_TRUE(next_frame(*listener, got));
    timespec real{}, mono{};
    clock_gettime(CLOCK_REALTIME, &real);
    clock_gettime(CLOCK_MONOTONIC, &mono);
    const std::int64_t offset_ns =
        (std::int64_t{real.tv_sec} - mono.tv_sec) * kSecond_ns + (real.tv_nsec - mono.tv_nsec);
    EXPECT_NEAR(static_cast<double>((got.stamp_ns + offset_ns) / 1000),
                static_cast<double>(record.wall_time_us), 2000.0)
        << lines[i];
  }
}

TEST_F(SocketCanVm, FdWorksOnVcan0AndIsRefusedOnClassicVcan1) {
  auto tx = open_bus("vcan0", true);
  auto rx = open_bus("vcan0", true);
  auto classic_rx = open_bus("vcan0", false);
  EXPECT_TRUE(tx->fd());
  hal::CanFrame fd = frame(0x321, {});
  fd.fd = true;
  fd.bit_rate_switch = true;
  fd.length = 48;
  for (std::uint8_t i = 0; i < 48; ++i) fd.data[i] = static_cast<std::uint8_t>(0xF0 ^ i);
  ASSERT_EQ(tx->send(fd), hal::Status::kOk);
  ASSERT_EQ(tx->send(frame(0x322, {1})), hal::Status::kOk);  // classic on an FD socket
  hal::CanFrame got;
  ASSERT_TRUE(next_frame(*rx, got));
  expect_same_frame(got, fd);
  EXPECT_EQ(got.data[47], 0xF0 ^ 47);
  ASSERT_TRUE(next_frame(*rx, got));
  EXPECT_EQ(got.id, 0x322u);
  EXPECT_FALSE(got.fd);
  // A classic socket on the same interface never sees the FD frame, only the classic one.
  ASSERT_TRUE(next_frame(*classic_rx, got));
  EXPECT_EQ(got.id, 0x322u);
  // A classic bus refuses FD frames itself.
  EXPECT_EQ(classic_rx->send(fd), hal::Status::kRejected);

  try {
    (void)open_bus("vcan1", /*fd=*/true);
    FAIL() << "FD opened on a classic interface";
  } catch (const std::runtime_error& error) {
    const std::string what = error.what();
    EXPECT_NE(what.find("CAN interface 'vcan1'"), std::string::npos) << what;
    EXPECT_NE(what.find("classic CAN interface (MTU 16)"), std::string::npos) << what;
  }
  auto classic = open_bus("vcan1");
  EXPECT_EQ(classic->interface_mtu(), CAN_MTU);
  EXPECT_EQ(classic->send(fd), hal::Status::kRejected);
  EXPECT_EQ(classic->send(frame(0x1, {1})), hal::Status::kOk);

  try {
    (void)open_bus("nosuchcan0");
    FAIL() << "opened a missing interface";
  } catch (const std::runtime_error& error) {
    EXPECT_NE(std::string(error.what()).find("no such network interface"), std::string::npos);
  }
  try {
    (void)open_bus("lo");
    FAIL() << "opened lo";
  } catch (const std::runtime_error& error) {
    EXPECT_NE(std::string(error.what()).find("not a CAN interface"), std::string::npos)
        << error.what();
  }
  EXPECT_EQ(read_can_bitrate("vcan0"), std::nullopt);  // vcan has no bit timing
}

TEST_F(SocketCanVm, FiltersPassOnlyTheirFramesButErrorFramesAlways) {
  auto tx = open_bus("vcan0");
  // TPDO1 of node 1 exactly (standard frames only: CAN_EFF_FLAG in the mask), and the
  // heartbeat range 0x700-0x77F (standard or extended: no flag in the mask).
  auto rx =
      open_bus("vcan0", false,
               {{.id = 0x181, .mask = CAN_SFF_MASK | CAN_EFF_FLAG}, {.id = 0x700, .mask = 0x780}});
  hal::CanFrame extended_181 = frame(0x181, {3});
  extended_181.extended_id = true;
  hal::CanFrame extended_701 = frame(0x701, {4});
  extended_701.extended_id = true;
  for (const auto& f : {frame(0x181, {1}), frame(0x182, {9}), frame(0x701, {2}), extended_181,
                        frame(0x780, {9}), extended_701, frame(0x77F, {5}), frame(0x080, {9})}) {
    ASSERT_EQ(tx->send(f), hal::Status::kOk);
  }
  hal::CanFrame error = frame(CAN_ERR_CRTL, {0, CAN_ERR_CRTL_RX_WARNING, 0, 0, 0, 0, 0, 99});
  error.error_frame = true;
  ASSERT_EQ(tx->send(error), hal::Status::kOk);
  ASSERT_EQ(tx->send(frame(0x77E, {0xEE})), hal::Status::kOk);  // the end
  std::vector<std::string> seen;
  hal::CanFrame got;
  while (next_frame(*rx, got, /*error_frames_too=*/true)) {
    seen.push_back(format_candump_frame(got));
    if (got.id == 0x77E && !got.error_frame) break;
  }
  EXPECT_EQ(seen, (std::vector<std::string>{"181#01", "701#02", "00000701#04", "77F#05",
                                            "20000004#0004000000000063", "77E#EE"}));
  EXPECT_EQ(rx->status().state, hal::CanBusState::kErrorWarning);
  EXPECT_EQ(rx->status().rx_error_count, 99);
}

TEST_F(SocketCanVm, ErrorFramesDriveTheBusStateThroughBusOffAndRestart) {
  auto rx = open_bus("vcan0");
  auto expect_state = [&](hal::CanBusState state) {
    hal::CanFrame got;
    ASSERT_TRUE(next_frame(*rx, got, true));
    EXPECT_TRUE(got.error_frame);
    EXPECT_EQ(rx->status().state, state);
  };
  // can-utils injects them as a controller would report them.
  ASSERT_EQ(shell("cansend vcan0 20000004#0020000000008000"), 0);  // TX passive, TEC 128
  expect_state(hal::CanBusState::kErrorPassive);
  EXPECT_EQ(rx->status().tx_error_count, 128);
  ASSERT_EQ(shell("cansend vcan0 20000040#0000000000000000"), 0);  // bus-off
  expect_state(hal::CanBusState::kBusOff);
  EXPECT_EQ(rx->send(frame(0x100, {})), hal::Status::kFault);  // no traffic while bus-off
  EXPECT_EQ(rx->send_batch(std::vector<hal::CanFrame>(3, frame(0x100, {}))), 0u);
  ASSERT_EQ(shell("cansend vcan0 20000100#0000000000000000"), 0);  // restarted
  expect_state(hal::CanBusState::kErrorActive);
  EXPECT_EQ(rx->send(frame(0x100, {})), hal::Status::kOk);
  EXPECT_EQ(rx->status().bus_off_count, 1u);
  EXPECT_EQ(rx->status().error_frames, 3u);
  EXPECT_EQ(rx->status().frames_received, 0u);
}

TEST_F(SocketCanVm, LoggedTrafficReplaysWithCanplayer) {
  const fs::path path = temp_file("traffic.log");
  auto peer = open_bus("vcan0", true);
  std::vector<hal::CanFrame> expected;
  {
    CanTrafficLog log(path.string());
    LoggingCanBus bus(open_bus("vcan0", true), log);
    hal::CanFrame fd = frame(0x201, {1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 12});
    fd.fd = true;
    hal::CanFrame extended = frame(0x18FF50E5, {0x55});
    extended.extended_id = true;
    expected = {frame(0x000, {0x01, 0x00}), frame(0x080, {}), fd, extended};
    for (const auto& f : expected) ASSERT_EQ(bus.send(f), hal::Status::kOk);
    const hal::CanFrame from_peer = frame(0x701, {0x05});
    ASSERT_EQ(peer->send(from_peer), hal::Status::kOk);
    hal::CanFrame got;
    ASSERT_TRUE(next_frame(bus, got));
    expected.push_back(from_peer);
    const CanLogReport report = log.close();
    ASSERT_TRUE(report.ok()) << report.error;
    EXPECT_EQ(report.records_written, expected.size());
  }
  auto receiver = open_bus("vcan0", true);
  ASSERT_EQ(shell("canplayer -I " + path.string() + " vcan0=vcan0"), 0);
  for (const auto& f : expected) {
    hal::CanFrame got;
    ASSERT_TRUE(next_frame(*receiver, got));
    expect_same_frame(got, f);
  }
  fs::remove(path);
}

TEST_F(SocketCanVm, FullTransmitQueueIsCountedAndNeverBlocks) {
  // vcan has no queue (qdisc noqueue): it never refuses a frame. A real controller's queue
  // fills when the bus is busy and the kernel returns ENOBUFS; a pfifo qdisc of limit 0 on a
  // vcan of our own makes every send meet a full queue the same way.
  ASSERT_EQ(shell("ip link add dev vcan7 type vcan && ip link set vcan7 up && "
                  "tc qdisc replace dev vcan7 root pfifo limit 0"),
            0);
  auto bus = open_bus("vcan7");
  EXPECT_EQ(bus->send(frame(0x100, {1})), hal::Status::kNoNewData);
  EXPECT_EQ(bus->send_batch(std::vector<hal::CanFrame>(5, frame(0x100, {1}))), 0u);
  hal::CanBusStatus status = bus->status();
  EXPECT_EQ(status.tx_queue_full, 2u);
  EXPECT_EQ(status.frames_dropped, 2u);
  EXPECT_EQ(status.frames_sent, 0u);
  EXPECT_EQ(status.state, hal::CanBusState::kErrorActive);  // a full queue is not a fault
  ASSERT_EQ(shell("tc qdisc del dev vcan7 root"), 0);
  EXPECT_EQ(bus->send(frame(0x100, {1})), hal::Status::kOk);
  // Down: a fault, and the state says so.
  ASSERT_EQ(shell("ip link set vcan7 down"), 0);
  EXPECT_EQ(bus->send(frame(0x100, {1})), hal::Status::kFault);
  EXPECT_EQ(bus->status().state, hal::CanBusState::kDown);
  ASSERT_EQ(shell("ip link del vcan7"), 0);
}

TEST_F(SocketCanVm, ReceiveOverrunsAreCounted) {
  // A reader that falls behind: the kernel drops what its socket buffer cannot hold and says
  // how many (SO_RXQ_OVFL) with the next frame it does queue: none of it is silent.
  auto tx = open_bus("vcan0");
  auto rx = open_bus("vcan0");
  constexpr std::size_t kFrames = 20'000;
  std::size_t sent = 0;
  const std::vector<hal::CanFrame> batch(16, frame(0x300, {1, 2, 3, 4, 5, 6, 7, 8}));
  while (sent < kFrames) sent += tx->send_batch(batch);
  hal::CanFrame got;
  std::uint64_t received = 0;
  while (rx->receive(got) == hal::Status::kOk) ++received;
  ASSERT_EQ(tx->send(frame(0x7FF, {})), hal::Status::kOk);  // carries the final drop count
  ++sent;
  ASSERT_TRUE(next_frame(*rx, got));
  EXPECT_EQ(got.id, 0x7FFu);
  ++received;
  const hal::CanBusStatus status = rx->status();
  EXPECT_GT(status.rx_overruns, 0u);
  EXPECT_EQ(status.frames_dropped, status.rx_overruns);
  EXPECT_EQ(status.frames_received, received);
  EXPECT_LE(received + status.rx_overruns, sent);
}

}  // namespace
}  // namespace cambio::can
