#pragma once

// Configure-time access to one CAN bus: send a frame, then take frames until what the caller
// waits for arrived or a deadline passed. Frames the caller does not consume go to a handler
// (boot-ups and EMCYs that arrive during an SDO transfer are not lost). May block and allocate:
// never for a loop.

#include <cstdint>
#include <functional>
#include <string>

#include "cambio/hal/can_bus.hpp"
#include "cambio/hal/clock.hpp"

namespace cambio::canopen {

class BusPump {
 public:
  /// Waits up to `timeout_ns` for a frame on `bus`. The default blocks in
  /// hal::CanBus::wait_for_frame; an in-process test steps its emulated drives (and its manual
  /// clock) here instead.
  using Waiter = std::function<void(hal::CanBus& bus, std::int64_t timeout_ns)>;
  using FrameHandler = std::function<void(const hal::CanFrame&)>;

  BusPump(hal::CanBus& bus, const hal::Clock& clock, Waiter wait = {});

  hal::CanBus& bus() { return bus_; }
  const hal::Clock& clock() const { return clock_; }

  /// Frames that `pump_until`'s consumer does not take.
  void set_other_frame_handler(FrameHandler handler) { other_ = std::move(handler); }

  /// Sends `frame`, waiting while the transmit queue is full, up to `timeout_ns`. Throws
  /// std::runtime_error naming the bus and `what` when the bus refuses it or stays full.
  void send(const hal::CanFrame& frame, std::int64_t timeout_ns, const std::string& what);

  /// Takes frames, offering each to `consume` (true = it was for the caller, else it goes to the
  /// other-frame handler), until `done()` or `timeout_ns` passes. Returns done().
  bool pump_until(const std::function<bool(const hal::CanFrame&)>& consume,
                  const std::function<bool()>& done, std::int64_t timeout_ns);

 private:
  hal::CanBus& bus_;
  const hal::Clock& clock_;
  Waiter wait_;
  FrameHandler other_;
};

}  // namespace cambio::canopen
