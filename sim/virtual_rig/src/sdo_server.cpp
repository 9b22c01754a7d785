#include "cambio/virtual_rig/sdo_server.hpp"

#include <algorithm>

namespace cambio::virtual_rig {

namespace {

using canopen::ObjectAddress;
using canopen::SdoAbortCode;

constexpr std::uint32_t code(SdoAbortCode abort) {
  return static_cast<std::uint32_t>(abort);
}

ObjectAddress address_of(const hal::CanFrame& frame) {
  return {static_cast<std::uint16_t>(canopen::get_le(frame.data, 1, 2)), frame.data[3]};
}

void start_response(hal::CanFrame& response, int node_id) {
  response = hal::CanFrame{};
  response.id = canopen::sdo_response_cob_id(node_id);
  response.length = 8;
}

void put_address(hal::CanFrame& response, ObjectAddress address) {
  canopen::put_le(response.data, 1, 2, address.index);
  response.data[3] = address.subindex;
}

}  // namespace

SdoServer::SdoServer(int node_id, SdoTarget& target) : node_id_(node_id), target_(target) {}

void SdoServer::abort(hal::CanFrame& response, ObjectAddress address,
                      std::uint32_t abort_code) noexcept {
  start_response(response, node_id_);
  response.data[0] = static_cast<std::uint8_t>(canopen::kSdoAbort << 5);
  put_address(response, address);
  canopen::put_le(response.data, 4, 4, abort_code);
  mode_ = Mode::kIdle;
}

bool SdoServer::handle(const hal::CanFrame& request, hal::CanFrame& response) noexcept {
  if (request.length != 8 || request.remote_request || request.fd) {
    ++malformed_;
    return false;
  }
  switch (canopen::sdo_command_specifier(request.data[0])) {
    case canopen::kSdoClientInitiateDownload:
      return initiate_download(request, response);
    case canopen::kSdoClientDownloadSegment:
      return download_segment(request, response);
    case canopen::kSdoClientInitiateUpload:
      return initiate_upload(request, response);
    case canopen::kSdoClientUploadSegment:
      return upload_segment(request, response);
    case canopen::kSdoAbort:
      mode_ = Mode::kIdle;  // The client gave up: no answer.
      return false;
    default:
      abort(response, address_of(request), code(SdoAbortCode::kInvalidCommandSpecifier));
      return true;
  }
}

bool SdoServer::initiate_download(const hal::CanFrame& request, hal::CanFrame& response) noexcept {
  // A new initiate ends any transfer in progress (the client started over).
  mode_ = Mode::kIdle;
  const ObjectAddress address = address_of(request);
  const std::uint8_t byte0 = request.data[0];
  const bool expedited = (byte0 & 0x02) != 0;
  const bool size_indicated = (byte0 & 0x01) != 0;
  if (const std::uint32_t forced = injected(address)) {
    abort(response, address, forced);
    return true;
  }
  if (expedited) {
    std::size_t size = 4;
    if (size_indicated) {
      size = 4 - ((byte0 >> 2) & 0x03);
    } else {
      // No size: the data is as long as the object (CiA 301: "unspecified number of bytes").
      const std::size_t object_size = target_.sdo_size(address);
      if (object_size > 0 && object_size < 4) size = object_size;
    }
    const std::uint32_t result =
        target_.sdo_write(address, std::span<const std::uint8_t>(request.data).subspan(4, size));
    if (result != 0) {
      abort(response, address, result);
      return true;
    }
  } else {
    size_known_ = size_indicated;
    size_ = size_indicated ? canopen::get_le(request.data, 4, 4) : 0;
    if (size_ > kMaxTransferBytes) {
      abort(response, address, code(SdoAbortCode::kOutOfMemory));
      return true;
    }
    mode_ = Mode::kDownloading;
    address_ = address;
    offset_ = 0;
    toggle_ = 0;
  }
  start_response(response, node_id_);
  response.data[0] = static_cast<std::uint8_t>(canopen::kSdoServerInitiateDownload << 5);
  put_address(response, address);
  return true;
}

bool SdoServer::download_segment(const hal::CanFrame& request, hal::CanFrame& response) noexcept {
  if (mode_ != Mode::kDownloading) {
    abort(response, address_of(request), code(SdoAbortCode::kInvalidCommandSpecifier));
    return true;
  }
  const std::uint8_t byte0 = request.data[0];
  const std::uint8_t toggle = (byte0 >> 4) & 0x01;
  if (toggle != toggle_) {
    abort(response, address_, code(SdoAbortCode::kToggleBitNotAlternated));
    return true;
  }
  const std::size_t bytes = 7 - ((byte0 >> 1) & 0x07);
  const bool last = (byte0 & 0x01) != 0;
  if (offset_ + bytes > kMaxTransferBytes || (size_known_ && offset_ + bytes > size_)) {
    abort(response, address_,
          code(size_known_ ? SdoAbortCode::kLengthTooHigh : SdoAbortCode::kOutOfMemory));
    return true;
  }
  std::copy_n(request.data.begin() + 1, bytes, buffer_.begin() + static_cast<long>(offset_));
  offset_ += bytes;
  if (last) {
    if (size_known_ && offset_ != size_) {
      abort(response, address_, code(SdoAbortCode::kLengthMismatch));
      return true;
    }
    const std::uint32_t result =
        target_.sdo_write(address_, std::span<const std::uint8_t>(buffer_.data(), offset_));
    if (result != 0) {
      abort(response, address_, result);
      return true;
    }
    mode_ = Mode::kIdle;
  }
  start_response(response, node_id_);
  response.data[0] =
      static_cast<std::uint8_t>(canopen::kSdoServerDownloadSegment << 5 | toggle_ << 4);
  toggle_ ^= 1;
  return true;
}

bool SdoServer::initiate_upload(const hal::CanFrame& request, hal::CanFrame& response) noexcept {
  mode_ = Mode::kIdle;
  const ObjectAddress address = address_of(request);
  if (const std::uint32_t forced = injected(address)) {
    abort(response, address, forced);
    return true;
  }
  std::size_t size = 0;
  const std::uint32_t result = target_.sdo_read(address, buffer_, size);
  if (result != 0) {
    abort(response, address, result);
    return true;
  }
  start_response(response, node_id_);
  put_address(response, address);
  if (size <= 4) {
    // Expedited, size indicated: n = 4 - size bytes of the data field carry nothing.
    response.data[0] = static_cast<std::uint8_t>(canopen::kSdoServerInitiateUpload << 5 |
                                                 (4 - size) << 2 | 0x02 | 0x01);
    std::copy_n(buffer_.begin(), size, response.data.begin() + 4);
    return true;
  }
  response.data[0] = static_cast<std::uint8_t>(canopen::kSdoServerInitiateUpload << 5 | 0x01);
  canopen::put_le(response.data, 4, 4, static_cast<std::uint32_t>(size));
  mode_ = Mode::kUploading;
  address_ = address;
  size_ = size;
  offset_ = 0;
  toggle_ = 0;
  return true;
}

bool SdoServer::upload_segment(const hal::CanFrame& request, hal::CanFrame& response) noexcept {
  if (mode_ != Mode::kUploading) {
    abort(response, address_of(request), code(SdoAbortCode::kInvalidCommandSpecifier));
    return true;
  }
  const std::uint8_t toggle = (request.data[0] >> 4) & 0x01;
  if (toggle != toggle_) {
    abort(response, address_, code(SdoAbortCode::kToggleBitNotAlternated));
    return true;
  }
  const std::size_t bytes = std::min<std::size_t>(7, size_ - offset_);
  const bool last = offset_ + bytes == size_;
  start_response(response, node_id_);
  response.data[0] = static_cast<std::uint8_t>(canopen::kSdoServerUploadSegment << 5 |
                                               toggle_ << 4 | (7 - bytes) << 1 | (last ? 1 : 0));
  std::copy_n(buffer_.begin() + static_cast<long>(offset_), bytes, response.data.begin() + 1);
  offset_ += bytes;
  toggle_ ^= 1;
  if (last) mode_ = Mode::kIdle;
  return true;
}

}  // namespace cambio::virtual_rig
