#include "cambio/canopen/bus_pump.hpp"

#include <algorithm>
#include <stdexcept>

namespace cambio::canopen {

namespace {
// How long one wait lasts at most, so deadlines are checked often.
constexpr std::int64_t kWaitSliceNs = 1'000'000;
}  // namespace

BusPump::BusPump(hal::CanBus& bus, const hal::Clock& clock, Waiter wait)
    : bus_(bus), clock_(clock), wait_(std::move(wait)) {
  if (!wait_) {
    wait_ = [](hal::CanBus& waited, std::int64_t timeout_ns) {
      (void)waited.wait_for_frame(timeout_ns);
    };
  }
}

void BusPump::send(const hal::CanFrame& frame, std::int64_t timeout_ns, const std::string& what) {
  const std::int64_t deadline_ns = clock_.now_ns() + timeout_ns;
  for (;;) {
    const hal::Status status = bus_.send(frame);
    if (status == hal::Status::kOk) return;
    if (status != hal::Status::kNoNewData) {
      throw std::runtime_error("CAN bus '" + bus_.name() + "': cannot send " + what + " (" +
                               std::string(hal::to_string(status)) + ")");
    }
    const std::int64_t now_ns = clock_.now_ns();
    if (now_ns >= deadline_ns) {
      throw std::runtime_error("CAN bus '" + bus_.name() + "': cannot send " + what +
                               ": the transmit queue stayed full");
    }
    wait_(bus_, std::min(kWaitSliceNs, deadline_ns - now_ns));
  }
}

bool BusPump::pump_until(const std::function<bool(const hal::CanFrame&)>& consume,
                         const std::function<bool()>& done, std::int64_t timeout_ns) {
  const std::int64_t deadline_ns = clock_.now_ns() + timeout_ns;
  hal::CanFrame frame;
  for (;;) {
    while (!done() && bus_.receive(frame) == hal::Status::kOk) {
      if (!consume(frame) && other_) other_(frame);
    }
    if (done()) return true;
    const std::int64_t now_ns = clock_.now_ns();
    if (now_ns >= deadline_ns) return false;
    wait_(bus_, std::min(kWaitSliceNs, deadline_ns - now_ns));
  }
}

}  // namespace cambio::canopen
