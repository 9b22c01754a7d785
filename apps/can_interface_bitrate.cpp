#include "can_interface_bitrate.hpp"

#include <filesystem>
#include <system_error>

#include "cambio/can/can_bitrate.hpp"

namespace cambio::app {

CanInterfaceBitrate query_can_interface_bitrate(const std::string& interface) {
  CanInterfaceBitrate result;
  std::error_code error;
  result.present = std::filesystem::exists("/sys/class/net/" + interface, error) && !error;
  // The bit rate is the kernel's (`ip link set can0 type can bitrate ...`), read over netlink.
  if (result.present) result.bitrate_bit_s = can::read_can_bitrate(interface);
  return result;
}

}  // namespace cambio::app
