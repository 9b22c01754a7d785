#include "cambio/can/socketcan_bus.hpp"

#include <linux/can.h>
#include <linux/can/raw.h>
#include <net/if.h>
#include <poll.h>
#include <sys/ioctl.h>
#include <sys/socket.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstring>
#include <ctime>
#include <stdexcept>

#include "cambio/can/can_error_frame.hpp"
#include "cambio/can/can_frame_rules.hpp"
#include "linux_can_frame.hpp"

namespace cambio::can {
namespace {

constexpr std::size_t kMaxBatch = 1024;

std::int64_t clock_ns(clockid_t clock) {
  timespec ts{};
  clock_gettime(clock, &ts);
  return std::int64_t{ts.tv_sec} * 1'000'000'000 + ts.tv_nsec;
}

// CLOCK_REALTIME - CLOCK_MONOTONIC, with the realtime read bracketed by two monotonic reads.
std::int64_t realtime_minus_monotonic_ns() {
  const std::int64_t before = clock_ns(CLOCK_MONOTONIC);
  const std::int64_t realtime = clock_ns(CLOCK_REALTIME);
  const std::int64_t after = clock_ns(CLOCK_MONOTONIC);
  return realtime - (before + (after - before) / 2);
}

std::string errno_text(int error) {
  return std::strerror(error);
}

[[noreturn]] void fail(const std::string& interface, const std::string& what) {
  throw std::runtime_error("CAN interface '" + interface + "': " + what);
}

// Space for the two control messages we ask for: the arrival time and the overrun count.
union ReceiveControl {
  cmsghdr align;
  char bytes[CMSG_SPACE(sizeof(timespec)) + CMSG_SPACE(sizeof(std::uint32_t))];
};

}  // namespace

struct SocketCanBus::State {
  std::string name;
  int socket_fd = -1;
  bool fd_frames = false;
  int mtu = CAN_MTU;
  std::size_t batch = 0;
  hal::CanBusStatus status;

  // Receive ring: one recvmmsg() fills `rx_frames` (decoded into `rx_ready`) when it is empty.
  std::vector<canfd_frame> rx_frames;
  std::vector<iovec> rx_iov;
  std::vector<ReceiveControl> rx_control;
  std::vector<mmsghdr> rx_msgs;
  std::vector<hal::CanFrame> rx_ready;
  std::size_t rx_head = 0;
  std::size_t rx_count = 0;
  std::uint32_t rx_overflow_seen = 0;  // SO_RXQ_OVFL's running total at the last read.

  // Transmit batch for sendmmsg().
  std::vector<canfd_frame> tx_frames;
  std::vector<iovec> tx_iov;
  std::vector<mmsghdr> tx_msgs;

  ~State() {
    if (socket_fd >= 0) ::close(socket_fd);
  }

  // Counts a refused send by its cause and returns what send() reports.
  hal::Status send_failed(int error) {
    switch (error) {
      case EAGAIN:
      case ENOBUFS:
        ++status.tx_queue_full;
        ++status.frames_dropped;
        return hal::Status::kNoNewData;
      case ENETDOWN:
      case ENXIO:
        status.state = hal::CanBusState::kDown;
        return hal::Status::kFault;
      case EINVAL:
        return hal::Status::kRejected;
      default:
        return hal::Status::kFault;
    }
  }

  void sent(std::size_t frames) {
    status.frames_sent += frames;
    if (status.state == hal::CanBusState::kDown) status.state = hal::CanBusState::kErrorActive;
  }

  // Decodes the `count` frames recvmmsg() returned into rx_ready; undecodable ones are counted.
  void decode_batch(std::size_t count) {
    const std::int64_t realtime_offset_ns = realtime_minus_monotonic_ns();
    rx_head = 0;
    rx_count = 0;
    for (std::size_t i = 0; i < count; ++i) {
      const msghdr& header = rx_msgs[i].msg_hdr;
      std::int64_t arrival_ns = 0;
      for (cmsghdr* c = CMSG_FIRSTHDR(&header); c != nullptr;
           c = CMSG_NXTHDR(const_cast<msghdr*>(&header), c)) {
        if (c->cmsg_level != SOL_SOCKET) continue;
        if (c->cmsg_type == SCM_TIMESTAMPNS) {
          timespec ts{};
          std::memcpy(&ts, CMSG_DATA(c), sizeof(ts));
          arrival_ns = std::int64_t{ts.tv_sec} * 1'000'000'000 + ts.tv_nsec - realtime_offset_ns;
        } else if (c->cmsg_type == SO_RXQ_OVFL) {
          std::uint32_t total = 0;
          std::memcpy(&total, CMSG_DATA(c), sizeof(total));
          const std::uint32_t lost = total - rx_overflow_seen;  // wraps like the kernel's counter
          rx_overflow_seen = total;
          status.rx_overruns += lost;
          status.frames_dropped += lost;
        }
      }
      const canfd_frame& raw = rx_frames[i];
      const unsigned bytes = rx_msgs[i].msg_len;
      const bool is_fd = bytes == CANFD_MTU;
      if ((bytes != CAN_MTU && !is_fd) || (header.msg_flags & MSG_TRUNC) != 0 ||
          raw.len > (is_fd ? CANFD_MAX_DLEN : CAN_MAX_DLEN) ||
          (is_fd && !is_can_fd_length(raw.len))) {
        ++status.malformed_frames;
        continue;
      }
      hal::CanFrame& frame = rx_ready[rx_count++];
      frame = detail::from_linux_frame(raw, is_fd);
      frame.stamp_ns = arrival_ns != 0 ? arrival_ns : clock_ns(CLOCK_MONOTONIC);
    }
  }

  // One recvmmsg() of up to `batch` frames; false when none is queued.
  bool refill() {
    for (std::size_t i = 0; i < batch; ++i) {
      rx_iov[i] = iovec{&rx_frames[i], sizeof(canfd_frame)};
      msghdr& header = rx_msgs[i].msg_hdr;
      header = msghdr{};
      header.msg_iov = &rx_iov[i];
      header.msg_iovlen = 1;
      header.msg_control = rx_control[i].bytes;
      header.msg_controllen = sizeof(rx_control[i].bytes);
      rx_msgs[i].msg_len = 0;
    }
    const int received =
        ::recvmmsg(socket_fd, rx_msgs.data(), static_cast<unsigned>(batch), MSG_DONTWAIT, nullptr);
    if (received <= 0) return false;
    decode_batch(static_cast<std::size_t>(received));
    return rx_count > 0;
  }
};

std::unique_ptr<SocketCanBus> SocketCanBus::open(const SocketCanOptions& options) {
  const std::string& interface = options.interface;
  if (interface.empty() || interface.size() >= IFNAMSIZ) {
    fail(interface, "an interface name is 1 to " + std::to_string(IFNAMSIZ - 1) + " characters");
  }
  if (options.batch_size == 0 || options.batch_size > kMaxBatch) {
    fail(interface, "batch_size must be 1 to " + std::to_string(kMaxBatch) + ", found " +
                        std::to_string(options.batch_size));
  }
  if (options.filters.size() > CAN_RAW_FILTER_MAX) {
    fail(interface, "at most " + std::to_string(CAN_RAW_FILTER_MAX) + " receive filters");
  }

  auto state = std::make_unique<State>();
  state->name = interface;
  state->socket_fd = ::socket(PF_CAN, SOCK_RAW | SOCK_NONBLOCK | SOCK_CLOEXEC, CAN_RAW);
  if (state->socket_fd < 0) {
    const int error = errno;
    if (error == EAFNOSUPPORT || error == EPROTONOSUPPORT) {
      fail(interface,
           "this kernel has no SocketCAN raw sockets (socket(PF_CAN): " + errno_text(error) +
               "); load them with `modprobe can-raw`, or run in the test guest "
               "(tests/can_vm/run_in_guest.sh)");
    }
    fail(interface, "socket(PF_CAN, SOCK_RAW, CAN_RAW): " + errno_text(error));
  }
  const int sock = state->socket_fd;

  ifreq request{};
  std::memcpy(request.ifr_name, interface.c_str(), interface.size() + 1);
  if (::ioctl(sock, SIOCGIFINDEX, &request) < 0) {
    const int error = errno;
    if (error == ENODEV) {
      fail(interface,
           "no such network interface (see `ip link show`; a virtual bus is made with "
           "`ip link add dev " +
               interface + " type vcan`)");
    }
    fail(interface, "ioctl(SIOCGIFINDEX): " + errno_text(error));
  }
  const int index = request.ifr_ifindex;
  if (::ioctl(sock, SIOCGIFMTU, &request) < 0)
    fail(interface, "ioctl(SIOCGIFMTU): " + errno_text(errno));
  state->mtu = request.ifr_mtu;
  if (state->mtu != CAN_MTU && state->mtu != CANFD_MTU) {
    fail(interface,
         "not a CAN interface (MTU " + std::to_string(state->mtu) + "; CAN has 16, CAN FD 72)");
  }
  if (options.fd && state->mtu != CANFD_MTU) {
    fail(interface,
         "is a classic CAN interface (MTU 16) and cannot carry CAN FD frames: set fd: false for "
         "its bus, or switch the interface to CAN FD (`ip link set " +
             interface + " type can bitrate ... dbitrate ... fd on`; for vcan `ip link set " +
             interface + " mtu 72`)");
  }
  if (::ioctl(sock, SIOCGIFFLAGS, &request) < 0)
    fail(interface, "ioctl(SIOCGIFFLAGS): " + errno_text(errno));
  state->status.state =
      (request.ifr_flags & IFF_UP) != 0 ? hal::CanBusState::kErrorActive : hal::CanBusState::kDown;

  auto set_option = [&](int level, int name, const void* value, socklen_t size, const char* what) {
    if (::setsockopt(sock, level, name, value, size) < 0) {
      fail(interface, std::string("setsockopt(") + what + "): " + errno_text(errno));
    }
  };
  state->fd_frames = options.fd;
  if (options.fd) {
    const int on = 1;
    set_option(SOL_CAN_RAW, CAN_RAW_FD_FRAMES, &on, sizeof(on), "CAN_RAW_FD_FRAMES");
  }
  if (!options.filters.empty()) {
    std::vector<can_filter> filters;
    for (const CanFilter& f : options.filters) filters.push_back(can_filter{f.id, f.mask});
    set_option(SOL_CAN_RAW, CAN_RAW_FILTER, filters.data(),
               static_cast<socklen_t>(filters.size() * sizeof(can_filter)), "CAN_RAW_FILTER");
  }
  const can_err_mask_t error_mask = CAN_ERR_MASK;
  set_option(SOL_CAN_RAW, CAN_RAW_ERR_FILTER, &error_mask, sizeof(error_mask),
             "CAN_RAW_ERR_FILTER");
  const int on = 1;
  set_option(SOL_SOCKET, SO_TIMESTAMPNS, &on, sizeof(on), "SO_TIMESTAMPNS");
  set_option(SOL_SOCKET, SO_RXQ_OVFL, &on, sizeof(on), "SO_RXQ_OVFL");

  sockaddr_can address{};
  address.can_family = AF_CAN;
  address.can_ifindex = index;
  if (::bind(sock, reinterpret_cast<const sockaddr*>(&address), sizeof(address)) < 0) {
    fail(interface, "bind: " + errno_text(errno));
  }

  const std::size_t batch = options.batch_size;
  state->batch = batch;
  state->rx_frames.resize(batch);
  state->rx_iov.resize(batch);
  state->rx_control.resize(batch);
  state->rx_msgs.resize(batch);
  state->rx_ready.resize(batch);
  state->tx_frames.resize(batch);
  state->tx_iov.resize(batch);
  state->tx_msgs.resize(batch);
  return std::unique_ptr<SocketCanBus>(new SocketCanBus(std::move(state)));
}

SocketCanBus::SocketCanBus(std::unique_ptr<State> state) : state_(std::move(state)) {}
SocketCanBus::~SocketCanBus() = default;

const std::string& SocketCanBus::name() const {
  return state_->name;
}
bool SocketCanBus::fd() const {
  return state_->fd_frames;
}
int SocketCanBus::interface_mtu() const {
  return state_->mtu;
}
hal::CanBusStatus SocketCanBus::status() const {
  return state_->status;
}

hal::Status SocketCanBus::send(const hal::CanFrame& frame) {
  State& s = *state_;
  if (can_frame_problem(frame, s.fd_frames) != nullptr) return hal::Status::kRejected;
  if (s.status.state == hal::CanBusState::kBusOff) return hal::Status::kFault;
  s.tx_frames[0] = detail::to_linux_frame(frame);
  const std::size_t size = frame.fd ? CANFD_MTU : CAN_MTU;
  const ssize_t written = ::send(s.socket_fd, &s.tx_frames[0], size, MSG_DONTWAIT);
  if (written < 0) return s.send_failed(errno);
  if (static_cast<std::size_t>(written) != size) return hal::Status::kFault;
  s.sent(1);
  return hal::Status::kOk;
}

std::size_t SocketCanBus::send_batch(std::span<const hal::CanFrame> frames) {
  State& s = *state_;
  std::size_t sent = 0;
  while (sent < frames.size() && s.status.state != hal::CanBusState::kBusOff) {
    // Prepare up to one batch, stopping before the first frame that cannot go out.
    std::size_t prepared = 0;
    const std::size_t wanted = std::min(s.batch, frames.size() - sent);
    while (prepared < wanted &&
           can_frame_problem(frames[sent + prepared], s.fd_frames) == nullptr) {
      const hal::CanFrame& frame = frames[sent + prepared];
      s.tx_frames[prepared] = detail::to_linux_frame(frame);
      s.tx_iov[prepared] = iovec{&s.tx_frames[prepared], frame.fd ? CANFD_MTU : CAN_MTU};
      msghdr& header = s.tx_msgs[prepared].msg_hdr;
      header = msghdr{};
      header.msg_iov = &s.tx_iov[prepared];
      header.msg_iovlen = 1;
      ++prepared;
    }
    if (prepared == 0) break;
    const int result =
        ::sendmmsg(s.socket_fd, s.tx_msgs.data(), static_cast<unsigned>(prepared), MSG_DONTWAIT);
    if (result < 0) {
      (void)s.send_failed(errno);
      break;
    }
    const auto accepted = static_cast<std::size_t>(result);
    s.sent(accepted);
    sent += accepted;
    if (accepted < prepared) {
      // sendmmsg() drops the error of the message that stopped it: one send() learns and
      // counts it (queue full, interface down), or carries on if the queue drained meanwhile.
      if (send(frames[sent]) != hal::Status::kOk) break;
      ++sent;
      continue;
    }
    if (prepared < wanted) break;
  }
  return sent;
}

hal::Status SocketCanBus::receive(hal::CanFrame& out) {
  State& s = *state_;
  if (s.rx_head == s.rx_count && !s.refill()) return hal::Status::kNoNewData;
  out = s.rx_ready[s.rx_head++];
  if (out.error_frame) {
    apply_can_error_frame(decode_can_error_frame(out), s.status);
  } else {
    ++s.status.frames_received;
  }
  return hal::Status::kOk;
}

hal::Status SocketCanBus::wait_for_frame(std::int64_t timeout_ns) {
  State& s = *state_;
  if (s.rx_head < s.rx_count) return hal::Status::kOk;
  pollfd watch{s.socket_fd, POLLIN, 0};
  const std::int64_t wait_ns = std::max<std::int64_t>(timeout_ns, 0);
  const timespec timeout{static_cast<time_t>(wait_ns / 1'000'000'000),
                         static_cast<long>(wait_ns % 1'000'000'000)};
  const int ready = ::ppoll(&watch, 1, &timeout, nullptr);
  return ready > 0 && (watch.revents & POLLIN) != 0 ? hal::Status::kOk : hal::Status::kNoNewData;
}

}  // namespace cambio::can
