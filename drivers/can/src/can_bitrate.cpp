#include "cambio/can/can_bitrate.hpp"

#include <linux/can/netlink.h>
#include <linux/if_link.h>
#include <linux/netlink.h>
#include <linux/rtnetlink.h>
#include <net/if.h>
#include <sys/socket.h>
#include <sys/time.h>
#include <unistd.h>

#include <array>
#include <cstring>

namespace cambio::can {
namespace {

// Closes the netlink socket on every path.
struct SocketGuard {
  int fd;
  ~SocketGuard() {
    if (fd >= 0) ::close(fd);
  }
};

// The attribute of `type` among the attributes in [data, data + length), or nullptr.
const rtattr* find_attribute(const void* data, int length, unsigned short type) {
  auto* attribute = static_cast<const rtattr*>(data);
  for (; RTA_OK(attribute, length); attribute = RTA_NEXT(attribute, length)) {
    if ((attribute->rta_type & NLA_TYPE_MASK) == type) return attribute;
  }
  return nullptr;
}

}  // namespace

std::optional<std::int64_t> read_can_bitrate(const std::string& interface) noexcept {
  if (interface.empty() || interface.size() >= IFNAMSIZ) return std::nullopt;
  const unsigned index = ::if_nametoindex(interface.c_str());
  if (index == 0) return std::nullopt;
  SocketGuard sock{::socket(AF_NETLINK, SOCK_RAW | SOCK_CLOEXEC, NETLINK_ROUTE)};
  if (sock.fd < 0) return std::nullopt;
  // The kernel answers at once; the timeout only guards against a netlink that never does.
  const timeval timeout{1, 0};
  if (::setsockopt(sock.fd, SOL_SOCKET, SO_RCVTIMEO, &timeout, sizeof(timeout)) < 0) {
    return std::nullopt;
  }

  struct {
    nlmsghdr header;
    ifinfomsg info;
  } request{};
  request.header.nlmsg_len = sizeof(request);
  request.header.nlmsg_type = RTM_GETLINK;
  request.header.nlmsg_flags = NLM_F_REQUEST;
  request.header.nlmsg_seq = 1;
  request.info.ifi_family = AF_UNSPEC;
  request.info.ifi_index = static_cast<int>(index);
  if (::send(sock.fd, &request, sizeof(request), 0) != static_cast<ssize_t>(sizeof(request))) {
    return std::nullopt;
  }

  alignas(nlmsghdr) std::array<char, 32768> reply{};
  const ssize_t received = ::recv(sock.fd, reply.data(), reply.size(), 0);
  if (received <= 0) return std::nullopt;
  auto length = static_cast<unsigned>(received);
  for (auto* header = reinterpret_cast<const nlmsghdr*>(reply.data()); NLMSG_OK(header, length);
       header = NLMSG_NEXT(header, length)) {
    if (header->nlmsg_type != RTM_NEWLINK) continue;  // NLMSG_ERROR: no such link
    const auto* info = static_cast<const ifinfomsg*>(NLMSG_DATA(header));
    if (info->ifi_index != static_cast<int>(index)) continue;
    const rtattr* link_info =
        find_attribute(IFLA_RTA(info), static_cast<int>(IFLA_PAYLOAD(header)), IFLA_LINKINFO);
    if (link_info == nullptr) return std::nullopt;
    const rtattr* kind = find_attribute(RTA_DATA(link_info),
                                        static_cast<int>(RTA_PAYLOAD(link_info)), IFLA_INFO_KIND);
    if (kind == nullptr ||
        std::strncmp(static_cast<const char*>(RTA_DATA(kind)), "can", RTA_PAYLOAD(kind)) != 0) {
      return std::nullopt;  // vcan, vxcan, ...: no bit timing
    }
    const rtattr* data = find_attribute(RTA_DATA(link_info),
                                        static_cast<int>(RTA_PAYLOAD(link_info)), IFLA_INFO_DATA);
    if (data == nullptr) return std::nullopt;
    const rtattr* timing =
        find_attribute(RTA_DATA(data), static_cast<int>(RTA_PAYLOAD(data)), IFLA_CAN_BITTIMING);
    if (timing == nullptr || RTA_PAYLOAD(timing) < sizeof(can_bittiming)) return std::nullopt;
    can_bittiming bit_timing{};
    std::memcpy(&bit_timing, RTA_DATA(timing), sizeof(bit_timing));
    if (bit_timing.bitrate == 0) return std::nullopt;
    return static_cast<std::int64_t>(bit_timing.bitrate);
  }
  return std::nullopt;
}

}  // namespace cambio::can
