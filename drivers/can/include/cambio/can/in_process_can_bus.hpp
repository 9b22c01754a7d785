#pragma once

#include <cstddef>
#include <memory>
#include <string>
#include <vector>

#include "cambio/hal/can_bus.hpp"
#include "cambio/hal/clock.hpp"

namespace cambio::can {

/// A CAN network inside one process, for unit tests and host benchmarks: every frame one
/// endpoint sends is delivered to every other endpoint (as on a bus; the sender does not see its
/// own frame). Each endpoint's receive queue is a fixed ring sized at construction; a full ring
/// drops the frame and counts it. Not thread-safe: all endpoints are used from one thread (a test
/// steps the master and the emulated drives in turn, deterministically).
class InProcessCanNetwork {
 public:
  /// `fd` makes it a CAN FD network (classic networks refuse FD frames, as a classic interface's
  /// MTU does). `clock` (optional, outlives the network) stamps received frames.
  explicit InProcessCanNetwork(bool fd = false, const hal::Clock* clock = nullptr);
  ~InProcessCanNetwork();
  InProcessCanNetwork(const InProcessCanNetwork&) = delete;
  InProcessCanNetwork& operator=(const InProcessCanNetwork&) = delete;

  /// A new endpoint named `name`; owned by the network, valid while it lives.
  hal::CanBus& add_endpoint(std::string name, std::size_t receive_capacity = 1024);

  /// Frames delivered so far (every send counts once, whatever the number of receivers).
  std::uint64_t frames_on_bus() const { return frames_on_bus_; }

 private:
  class Endpoint;
  void deliver(const Endpoint& sender, const hal::CanFrame& frame);

  bool fd_;
  const hal::Clock* clock_;
  std::vector<std::unique_ptr<Endpoint>> endpoints_;
  std::uint64_t frames_on_bus_ = 0;
};

}  // namespace cambio::can
