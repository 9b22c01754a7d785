#include "cambio/canopen/sdo_client.hpp"

#include <algorithm>
#include <cstdio>

namespace cambio::canopen {

namespace {

constexpr std::size_t kSdoFrameBytes = 8;
constexpr std::size_t kExpeditedBytes = 4;
constexpr std::size_t kSegmentBytes = 7;

hal::CanFrame sdo_frame(int node_id) {
  hal::CanFrame frame;
  frame.id = sdo_request_cob_id(node_id);
  frame.length = kSdoFrameBytes;
  return frame;
}

void put_address(hal::CanFrame& frame, ObjectAddress object) {
  put_le(frame.data, 1, 2, object.index);
  frame.data[3] = object.subindex;
}

ObjectAddress address_of(const hal::CanFrame& frame) {
  return {static_cast<std::uint16_t>(get_le(frame.data, 1, 2)), frame.data[3]};
}

}  // namespace

// Why the server's answer to our initiate request does not fit it: another command, or another
// object than the one asked for (SdoAbortCode{} when it fits).
SdoAbortCode SdoClient::initiate_mismatch(const hal::CanFrame& frame,
                                          std::uint8_t expected_scs) const {
  if (sdo_command_specifier(frame.data[0]) != expected_scs) {
    return SdoAbortCode::kInvalidCommandSpecifier;
  }
  if (!(address_of(frame) == object_)) return SdoAbortCode::kGeneralError;
  return SdoAbortCode{};
}

hal::CanFrame SdoClient::start_download(ObjectAddress object, std::span<const std::uint8_t> data,
                                        std::int64_t now_ns, std::int64_t timeout_ns) {
  state_ = State::kBusy;
  failure_ = Failure::kNone;
  upload_ = false;
  initiated_ = false;
  toggle_ = false;
  object_ = object;
  abort_code_ = 0;
  timeout_ns_ = timeout_ns;
  deadline_ns_ = now_ns + timeout_ns;
  download_data_ = data;
  download_offset_ = 0;
  upload_size_ = 0;

  hal::CanFrame frame = sdo_frame(node_id_);
  put_address(frame, object);
  if (!data.empty() && data.size() <= kExpeditedBytes) {
    // ccs 1, n = unused bytes, e = 1 (expedited), s = 1 (size indicated).
    frame.data[0] = static_cast<std::uint8_t>(kSdoClientInitiateDownload << 5 |
                                              (kExpeditedBytes - data.size()) << 2 | 0x03);
    std::copy(data.begin(), data.end(), frame.data.begin() + 4);
  } else {
    // ccs 1, e = 0, s = 1: the size in bytes 4..7, segments follow.
    frame.data[0] = static_cast<std::uint8_t>(kSdoClientInitiateDownload << 5 | 0x01);
    put_le(frame.data, 4, 4, static_cast<std::uint32_t>(data.size()));
  }
  return frame;
}

hal::CanFrame SdoClient::start_upload(ObjectAddress object, std::int64_t now_ns,
                                      std::int64_t timeout_ns) {
  state_ = State::kBusy;
  failure_ = Failure::kNone;
  upload_ = true;
  initiated_ = false;
  toggle_ = false;
  object_ = object;
  abort_code_ = 0;
  timeout_ns_ = timeout_ns;
  deadline_ns_ = now_ns + timeout_ns;
  download_data_ = {};
  upload_size_ = 0;
  upload_expected_ = 0;
  upload_size_known_ = false;

  hal::CanFrame frame = sdo_frame(node_id_);
  frame.data[0] = kSdoClientInitiateUpload << 5;
  put_address(frame, object);
  return frame;
}

bool SdoClient::poll(std::int64_t now_ns, hal::CanFrame& reply) {
  if (state_ != State::kBusy || now_ns < deadline_ns_) return false;
  const bool sent = abort(static_cast<std::uint32_t>(SdoAbortCode::kTimeout), reply);
  failure_ = Failure::kTimeout;
  return sent;
}

bool SdoClient::on_frame(const hal::CanFrame& frame, std::int64_t now_ns, hal::CanFrame& reply) {
  if (state_ != State::kBusy || frame.id != sdo_response_cob_id(node_id_) || frame.extended_id ||
      frame.remote_request || frame.error_frame) {
    return false;
  }
  if (frame.length != kSdoFrameBytes) {
    return abort(static_cast<std::uint32_t>(SdoAbortCode::kGeneralError), reply);
  }
  if (sdo_command_specifier(frame.data[0]) == kSdoAbort) {
    state_ = State::kAborted;
    failure_ = Failure::kServerAbort;
    abort_code_ = get_le(frame.data, 4, 4);
    return false;
  }
  // Each answer restarts the timeout: it bounds one request, not a whole segmented transfer.
  deadline_ns_ = now_ns + timeout_ns_;
  return upload_ ? on_upload_answer(frame, reply) : on_download_answer(frame, reply);
}

bool SdoClient::on_download_answer(const hal::CanFrame& frame, hal::CanFrame& reply) {
  const std::uint8_t scs = sdo_command_specifier(frame.data[0]);
  if (!initiated_) {
    if (const SdoAbortCode code = initiate_mismatch(frame, kSdoServerInitiateDownload);
        code != SdoAbortCode{}) {
      return abort(static_cast<std::uint32_t>(code), reply);
    }
    initiated_ = true;
    if (!download_data_.empty() && download_data_.size() <= kExpeditedBytes) {
      state_ = State::kDone;
      return false;
    }
    reply = next_download_segment();
    return true;
  }
  if (scs != kSdoServerDownloadSegment) {
    return abort(static_cast<std::uint32_t>(SdoAbortCode::kInvalidCommandSpecifier), reply);
  }
  // The server echoes the toggle bit of the segment it acknowledges (toggle_ was flipped since).
  const bool acknowledged_toggle = (frame.data[0] & 0x10) != 0;
  if (acknowledged_toggle == toggle_) {
    return abort(static_cast<std::uint32_t>(SdoAbortCode::kToggleBitNotAlternated), reply);
  }
  if (download_offset_ >= download_data_.size()) {
    state_ = State::kDone;
    return false;
  }
  reply = next_download_segment();
  return true;
}

hal::CanFrame SdoClient::next_download_segment() {
  const std::size_t bytes = std::min(kSegmentBytes, download_data_.size() - download_offset_);
  const bool last = download_offset_ + bytes >= download_data_.size();
  hal::CanFrame frame = sdo_frame(node_id_);
  frame.data[0] = static_cast<std::uint8_t>(kSdoClientDownloadSegment << 5 | (toggle_ ? 0x10 : 0) |
                                            (kSegmentBytes - bytes) << 1 | (last ? 0x01 : 0));
  std::copy_n(download_data_.begin() + static_cast<std::ptrdiff_t>(download_offset_), bytes,
              frame.data.begin() + 1);
  download_offset_ += bytes;
  toggle_ = !toggle_;
  return frame;
}

bool SdoClient::on_upload_answer(const hal::CanFrame& frame, hal::CanFrame& reply) {
  const std::uint8_t scs = sdo_command_specifier(frame.data[0]);
  if (!initiated_) {
    if (const SdoAbortCode code = initiate_mismatch(frame, kSdoServerInitiateUpload);
        code != SdoAbortCode{}) {
      return abort(static_cast<std::uint32_t>(code), reply);
    }
    initiated_ = true;
    const bool expedited = (frame.data[0] & 0x02) != 0;
    const bool size_indicated = (frame.data[0] & 0x01) != 0;
    if (expedited) {
      const std::size_t bytes =
          size_indicated ? kExpeditedBytes - ((frame.data[0] >> 2) & 0x03) : kExpeditedBytes;
      (void)append(std::span(frame.data).subspan(4, bytes));
      state_ = State::kDone;
      return false;
    }
    upload_size_known_ = size_indicated;
    upload_expected_ = size_indicated ? get_le(frame.data, 4, 4) : 0;
    if (upload_size_known_ && upload_expected_ > kMaxUploadBytes) {
      return abort(static_cast<std::uint32_t>(SdoAbortCode::kOutOfMemory), reply);
    }
    reply = request_frame();
    return true;
  }
  if (scs != kSdoServerUploadSegment) {
    return abort(static_cast<std::uint32_t>(SdoAbortCode::kInvalidCommandSpecifier), reply);
  }
  if (((frame.data[0] & 0x10) != 0) != toggle_) {
    return abort(static_cast<std::uint32_t>(SdoAbortCode::kToggleBitNotAlternated), reply);
  }
  const std::size_t bytes = kSegmentBytes - ((frame.data[0] >> 1) & 0x07);
  if (!append(std::span(frame.data).subspan(1, bytes))) {
    return abort(static_cast<std::uint32_t>(SdoAbortCode::kOutOfMemory), reply);
  }
  toggle_ = !toggle_;
  if ((frame.data[0] & 0x01) != 0) {
    if (upload_size_known_ && upload_size_ != upload_expected_) {
      return abort(static_cast<std::uint32_t>(SdoAbortCode::kLengthMismatch), reply);
    }
    state_ = State::kDone;
    return false;
  }
  reply = request_frame();
  return true;
}

hal::CanFrame SdoClient::request_frame() const {
  hal::CanFrame frame = sdo_frame(node_id_);
  frame.data[0] = static_cast<std::uint8_t>(kSdoClientUploadSegment << 5 | (toggle_ ? 0x10 : 0));
  return frame;
}

bool SdoClient::append(std::span<const std::uint8_t> bytes) {
  if (upload_size_ + bytes.size() > kMaxUploadBytes) return false;
  std::copy(bytes.begin(), bytes.end(),
            upload_data_.begin() + static_cast<std::ptrdiff_t>(upload_size_));
  upload_size_ += bytes.size();
  return true;
}

bool SdoClient::abort(std::uint32_t code, hal::CanFrame& reply) {
  state_ = State::kAborted;
  failure_ = Failure::kClientAbort;
  abort_code_ = code;
  reply = sdo_frame(node_id_);
  reply.data[0] = kSdoAbort << 5;
  put_address(reply, object_);
  put_le(reply.data, 4, 4, code);
  return true;
}

void SdoClient::describe_failure(std::span<char> out) const {
  if (out.empty()) return;
  const std::string_view name = sdo_abort_name(abort_code_);
  const char* how = failure_ == Failure::kServerAbort ? "aborted by the drive"
                    : failure_ == Failure::kTimeout   ? "not answered in time"
                                                      : "aborted by the master on a bad answer";
  std::snprintf(out.data(), out.size(), "SDO %s 0x%04X:%02X %s: 0x%08X (%.*s)",
                upload_ ? "upload of" : "download to", static_cast<unsigned>(object_.index),
                static_cast<unsigned>(object_.subindex), how, abort_code_,
                static_cast<int>(name.size()), name.data());
}

}  // namespace cambio::canopen
