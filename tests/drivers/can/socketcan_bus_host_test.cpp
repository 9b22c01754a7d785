// What SocketCanBus and read_can_bitrate do on any host, with or without a kernel CAN stack:
// bad options are refused before touching the kernel, a kernel without PF_CAN gets a message
// that says so and what to do, and the bit-rate query never throws.
#include <gtest/gtest.h>
#include <sys/socket.h>
#include <unistd.h>

#include <linux/can.h>

#include "cambio/can/can_bitrate.hpp"
#include "cambio/can/socketcan_bus.hpp"

namespace cambio::can {
namespace {

std::string open_error(const SocketCanOptions& options) {
  try {
    (void)SocketCanBus::open(options);
  } catch (const std::runtime_error& error) {
    return error.what();
  }
  return "";
}

bool kernel_has_can() {
  const int fd = ::socket(PF_CAN, SOCK_RAW, CAN_RAW);
  if (fd < 0) return false;
  ::close(fd);
  return true;
}

TEST(SocketCanBusHost, RefusesBadOptionsNamingThem) {
  EXPECT_NE(open_error({.interface = "", .fd = false, .filters = {}, .batch_size = 64})
                .find("1 to 15 characters"),
            std::string::npos);
  EXPECT_NE(open_error({.interface = "can0", .fd = false, .filters = {}, .batch_size = 0})
                .find("batch_size must be 1 to 1024, found 0"),
            std::string::npos);
  SocketCanOptions many{.interface = "can0", .fd = false, .filters = {}, .batch_size = 8};
  many.filters.resize(600);
  EXPECT_NE(open_error(many).find("at most 512 receive filters"), std::string::npos);
}

TEST(SocketCanBusHost, SaysPlainlyWhenTheKernelHasNoCan) {
  if (kernel_has_can()) GTEST_SKIP() << "this kernel has PF_CAN; the guest tests cover it";
  const std::string message =
      open_error({.interface = "vcan0", .fd = false, .filters = {}, .batch_size = 64});
  EXPECT_NE(message.find("CAN interface 'vcan0'"), std::string::npos) << message;
  EXPECT_NE(message.find("no SocketCAN"), std::string::npos) << message;
  EXPECT_NE(message.find("modprobe can-raw"), std::string::npos) << message;
}

TEST(SocketCanBusHost, BitrateIsAbsentForNonCanAndMissingInterfaces) {
  EXPECT_EQ(read_can_bitrate("lo"), std::nullopt);  // exists, not CAN
  EXPECT_EQ(read_can_bitrate("nosuchcan9"), std::nullopt);
  EXPECT_EQ(read_can_bitrate(""), std::nullopt);
  EXPECT_EQ(read_can_bitrate("a-name-longer-than-ifnamsiz"), std::nullopt);
}

}  // namespace
}  // namespace cambio::can
