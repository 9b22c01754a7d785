#include "cambio/can/in_process_can_bus.hpp"

namespace cambio::can {

class InProcessCanNetwork::Endpoint final : public hal::CanBus {
 public:
  Endpoint(InProcessCanNetwork& network, std::string name, std::size_t capacity)
      : network_(network), name_(std::move(name)), ring_(capacity == 0 ? 1 : capacity) {
    status_.state = hal::CanBusState::kErrorActive;
  }

  const std::string& name() const override { return name_; }

  hal::Status send(const hal::CanFrame& frame) override {
    const std::uint8_t max_length =
        frame.fd ? hal::CanFrame::kMaxFdDataBytes : hal::CanFrame::kMaxClassicDataBytes;
    if ((frame.fd && !network_.fd_) || frame.length > max_length || frame.error_frame ||
        frame.id > (frame.extended_id ? 0x1FFF'FFFFu : 0x7FFu)) {
      return hal::Status::kRejected;
    }
    network_.deliver(*this, frame);
    ++status_.frames_sent;
    return hal::Status::kOk;
  }

  hal::Status receive(hal::CanFrame& out) override {
    if (count_ == 0) return hal::Status::kNoNewData;
    out = ring_[head_];
    head_ = (head_ + 1) % ring_.size();
    --count_;
    ++status_.frames_received;
    return hal::Status::kOk;
  }

  hal::CanBusStatus status() const override { return status_; }

  // One thread steps every endpoint: nothing can arrive while this one waits.
  hal::Status wait_for_frame(std::int64_t /*timeout_ns*/) override {
    return count_ > 0 ? hal::Status::kOk : hal::Status::kNoNewData;
  }

  void push(const hal::CanFrame& frame, std::int64_t stamp_ns) {
    if (count_ == ring_.size()) {
      ++status_.frames_dropped;
      return;
    }
    hal::CanFrame& slot = ring_[(head_ + count_) % ring_.size()];
    slot = frame;
    slot.stamp_ns = stamp_ns;
    ++count_;
  }

 private:
  InProcessCanNetwork& network_;
  std::string name_;
  std::vector<hal::CanFrame> ring_;
  std::size_t head_ = 0;
  std::size_t count_ = 0;
  hal::CanBusStatus status_;
};

InProcessCanNetwork::InProcessCanNetwork(bool fd, const hal::Clock* clock)
    : fd_(fd), clock_(clock) {}

InProcessCanNetwork::~InProcessCanNetwork() = default;

hal::CanBus& InProcessCanNetwork::add_endpoint(std::string name, std::size_t receive_capacity) {
  endpoints_.push_back(std::make_unique<Endpoint>(*this, std::move(name), receive_capacity));
  return *endpoints_.back();
}

void InProcessCanNetwork::deliver(const Endpoint& sender, const hal::CanFrame& frame) {
  const std::int64_t stamp_ns = clock_ != nullptr ? clock_->now_ns() : 0;
  for (const auto& endpoint : endpoints_) {
    if (endpoint.get() != &sender) endpoint->push(frame, stamp_ns);
  }
  ++frames_on_bus_;
}

}  // namespace cambio::can
