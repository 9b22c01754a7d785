#include "cambio/canopen/node_reconfiguration.hpp"

#include <cstdio>

#include "cambio/canopen/nmt_master.hpp"

namespace cambio::canopen {

namespace {

std::uint32_t mask_of(const ObjectWrite& write) {
  return write.bytes >= 4 ? 0xFFFF'FFFFu : (1u << (8 * write.bytes)) - 1u;
}

// describe_value() without the std::string: "32595 (0x00007F53)".
void format_value(char* out, std::size_t size, const ObjectWrite& write, std::uint32_t raw) {
  raw &= mask_of(write);
  if (write.is_signed) {
    std::snprintf(out, size, "%d (0x%0*X)", sign_extend(raw, write.bytes), 2 * write.bytes, raw);
  } else {
    std::snprintf(out, size, "%u (0x%0*X)", raw, 2 * write.bytes, raw);
  }
}

}  // namespace

std::vector<ReconfigurationStep> reconfiguration_plan(std::span<const ObjectWrite> writes) {
  using Kind = ReconfigurationStep::Kind;
  std::vector<ReconfigurationStep> plan;
  for (const ObjectWrite& write : writes) plan.push_back({Kind::kWrite, write});
  // The read-back verify_objects() makes: the last write to each object, where marked verify.
  for (std::size_t i = 0; i < writes.size(); ++i) {
    bool overwritten_later = false;
    for (std::size_t j = i + 1; j < writes.size(); ++j) {
      overwritten_later = overwritten_later || writes[j].object == writes[i].object;
    }
    if (writes[i].verify && !overwritten_later) plan.push_back({Kind::kVerify, writes[i]});
  }
  plan.push_back({Kind::kReadStatusword, {cia402::kStatusword, 0, 2}});
  plan.push_back({Kind::kReadPosition, {cia402::kPositionActualValue, 0, 4, true}});
  plan.push_back({Kind::kNmtStart, {}});
  return plan;
}

void NodeReconfiguration::start(int node_id, std::span<const ReconfigurationStep> plan,
                                std::int64_t timeout_ns, std::int64_t now_ns) {
  client_ = SdoClient(node_id);
  plan_ = plan;
  step_ = 0;
  timeout_ns_ = timeout_ns;
  state_ = State::kRunning;
  pending_ = false;
  feedback_ = {};
  error_ = {};
  error_.node_id = node_id;
  begin_step(now_ns);
}

void NodeReconfiguration::begin_step(std::int64_t now_ns) {
  if (step_ >= plan_.size()) {
    state_ = State::kDone;
    return;
  }
  const ReconfigurationStep& step = plan_[step_];
  switch (step.kind) {
    case ReconfigurationStep::Kind::kWrite:
      put_le(download_, 0, step.write.bytes, step.write.value);
      set_pending(client_.start_download(
          step.write.object, std::span(download_).first(step.write.bytes), now_ns, timeout_ns_));
      return;
    case ReconfigurationStep::Kind::kVerify:
    case ReconfigurationStep::Kind::kReadStatusword:
    case ReconfigurationStep::Kind::kReadPosition:
      set_pending(client_.start_upload(step.write.object, now_ns, timeout_ns_));
      return;
    case ReconfigurationStep::Kind::kNmtStart:
      set_pending(nmt_frame(NmtCommand::kStart, client_.node_id()));
      return;
  }
}

void NodeReconfiguration::on_sent(std::int64_t now_ns) {
  pending_ = false;
  // NMT start is unconfirmed (CiA 301): sent is done.
  if (state_ == State::kRunning && step_ < plan_.size() &&
      plan_[step_].kind == ReconfigurationStep::Kind::kNmtStart) {
    ++step_;
    begin_step(now_ns);
  }
}

void NodeReconfiguration::on_frame(const hal::CanFrame& frame, std::int64_t now_ns) {
  if (state_ != State::kRunning) return;
  hal::CanFrame reply;
  if (client_.on_frame(frame, now_ns, reply)) set_pending(reply);
  if (client_.state() == SdoClient::State::kDone) {
    finish_step(now_ns);
  } else if (client_.state() == SdoClient::State::kAborted) {
    fail_sdo();
  }
}

void NodeReconfiguration::poll(std::int64_t now_ns) {
  if (state_ != State::kRunning || client_.state() != SdoClient::State::kBusy) return;
  hal::CanFrame reply;
  if (client_.poll(now_ns, reply)) {
    set_pending(reply);  // Tell the drive, so it does not wait for the rest of the transfer.
    fail_sdo();
  }
}

void NodeReconfiguration::finish_step(std::int64_t now_ns) {
  const ReconfigurationStep& step = plan_[step_];
  if (step.kind != ReconfigurationStep::Kind::kWrite) {
    const std::span<const std::uint8_t> data = client_.data();
    if (data.empty() || data.size() > 4) {
      std::snprintf(error_.text.data(), error_.text.size(),
                    "node %d: SDO upload of 0x%04X:%02X answered %zu bytes, expected 1 to 4",
                    client_.node_id(), static_cast<unsigned>(step.write.object.index),
                    static_cast<unsigned>(step.write.object.subindex), data.size());
      error_.abort_code = static_cast<std::uint32_t>(SdoAbortCode::kLengthMismatch);
      state_ = State::kFailed;
      return;
    }
    const std::uint32_t raw = get_le(data, 0, data.size());
    if (step.kind == ReconfigurationStep::Kind::kVerify &&
        (raw & mask_of(step.write)) != (step.write.value & mask_of(step.write))) {
      std::array<char, 40> written{};
      std::array<char, 40> read{};
      format_value(written.data(), written.size(), step.write, step.write.value);
      format_value(read.data(), read.size(), step.write, raw);
      std::snprintf(error_.text.data(), error_.text.size(),
                    "node %d: object 0x%04X:%02X written %s, read back %s", client_.node_id(),
                    static_cast<unsigned>(step.write.object.index),
                    static_cast<unsigned>(step.write.object.subindex), written.data(), read.data());
      state_ = State::kFailed;
      return;
    }
    if (step.kind == ReconfigurationStep::Kind::kReadStatusword) {
      feedback_.statusword = static_cast<std::uint16_t>(raw);
    } else if (step.kind == ReconfigurationStep::Kind::kReadPosition) {
      feedback_.position_counts = sign_extend(raw, data.size());
    }
  }
  ++step_;
  begin_step(now_ns);
}

void NodeReconfiguration::fail_sdo() {
  std::array<char, 160> failure{};
  client_.describe_failure(failure);
  std::snprintf(error_.text.data(), error_.text.size(), "node %d: %s", client_.node_id(),
                failure.data());
  error_.abort_code = client_.abort_code();
  state_ = State::kFailed;
}

void NodeReconfiguration::fail(const char* reason) {
  if (state_ != State::kRunning) return;
  std::snprintf(error_.text.data(), error_.text.size(), "node %d: %s", client_.node_id(), reason);
  state_ = State::kFailed;
}

}  // namespace cambio::canopen
