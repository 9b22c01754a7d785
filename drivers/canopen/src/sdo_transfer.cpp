#include "cambio/canopen/sdo_transfer.hpp"

#include <array>
#include <cmath>
#include <cstdio>

#include "cambio/canopen/sdo_client.hpp"

namespace cambio::canopen {

namespace {

std::string hex32(std::uint32_t value) {
  std::array<char, 16> text{};
  std::snprintf(text.data(), text.size(), "0x%08X", value);
  return text.data();
}

std::int64_t to_ns(double seconds) {
  return static_cast<std::int64_t>(std::llround(seconds * 1e9));
}

void run(BusPump& pump, SdoClient& client, const hal::CanFrame& first, double timeout_s) {
  const std::string what =
      std::string(client.is_upload() ? "upload of " : "download to ") + to_string(client.object());
  const std::string prefix = "node " + std::to_string(client.node_id()) + ": SDO " + what;
  pump.send(first, to_ns(timeout_s), "the SDO request (" + prefix + ")");
  hal::CanFrame reply;
  bool timed_out = false;
  const auto consume = [&](const hal::CanFrame& frame) {
    if (frame.id != sdo_response_cob_id(client.node_id())) return false;
    if (client.on_frame(frame, pump.clock().now_ns(), reply)) {
      pump.send(reply, to_ns(timeout_s), "the SDO request (" + prefix + ")");
    }
    return true;
  };
  const auto done = [&] { return client.state() != SdoClient::State::kBusy; };
  // The client's own deadline is per answer; the pump waits until the client gives up.
  while (!pump.pump_until(consume, done, to_ns(timeout_s))) {
    if (client.poll(pump.clock().now_ns(), reply)) {
      timed_out = true;
      // Tell the server, so it does not wait for the rest of the transfer; best effort.
      (void)pump.bus().send(reply);
      break;
    }
  }
  if (client.state() == SdoClient::State::kDone) return;
  const std::uint32_t code = client.abort_code();
  const std::string_view name = sdo_abort_name(code);
  const std::string meaning = hex32(code) + (name.empty() ? "" : " (" + std::string(name) + ")");
  if (timed_out) {
    throw SdoError(prefix + ": no answer within " + std::to_string(timeout_s) + " s", code);
  }
  if (client.failure() == SdoClient::Failure::kServerAbort) {
    throw SdoError(prefix + " aborted by the drive: " + meaning, code);
  }
  throw SdoError(prefix + " aborted by the master on a bad answer: " + meaning, code);
}

}  // namespace

std::string to_string(ObjectAddress object) {
  std::array<char, 16> text{};
  std::snprintf(text.data(), text.size(), "0x%04X:%02X", static_cast<unsigned>(object.index),
                static_cast<unsigned>(object.subindex));
  return text.data();
}

std::vector<std::uint8_t> sdo_upload(BusPump& pump, int node_id, ObjectAddress object,
                                     double timeout_s) {
  SdoClient client(node_id);
  run(pump, client, client.start_upload(object, pump.clock().now_ns(), to_ns(timeout_s)),
      timeout_s);
  return {client.data().begin(), client.data().end()};
}

void sdo_download(BusPump& pump, int node_id, ObjectAddress object,
                  std::span<const std::uint8_t> data, double timeout_s) {
  SdoClient client(node_id);
  run(pump, client, client.start_download(object, data, pump.clock().now_ns(), to_ns(timeout_s)),
      timeout_s);
}

void sdo_write_value(BusPump& pump, int node_id, ObjectAddress object, std::uint32_t value,
                     std::size_t bytes, double timeout_s) {
  std::array<std::uint8_t, 4> data{};
  put_le(data, 0, bytes, value);
  sdo_download(pump, node_id, object, std::span(data).first(bytes), timeout_s);
}

std::uint32_t sdo_read_value(BusPump& pump, int node_id, ObjectAddress object, double timeout_s) {
  const std::vector<std::uint8_t> data = sdo_upload(pump, node_id, object, timeout_s);
  if (data.empty() || data.size() > 4) {
    throw SdoError("node " + std::to_string(node_id) + ": SDO upload of " + to_string(object) +
                       " answered " + std::to_string(data.size()) + " bytes, expected 1 to 4",
                   static_cast<std::uint32_t>(SdoAbortCode::kLengthMismatch));
  }
  return get_le(data, 0, data.size());
}

}  // namespace cambio::canopen
