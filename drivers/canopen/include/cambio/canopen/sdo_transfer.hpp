#pragma once

// Blocking SDO transfers for configure time: runs an SdoClient over a BusPump until it is done,
// aborted or timed out. Errors name the node, the object and the abort code with its CiA 301
// meaning.

#include <cstdint>
#include <span>
#include <stdexcept>
#include <string>
#include <vector>

#include "cambio/canopen/bus_pump.hpp"
#include "cambio/canopen/protocol.hpp"

namespace cambio::canopen {

/// An SDO transfer that did not complete. what(): e.g. "node 5: SDO upload of 0x1008:00
/// aborted by the drive: 0x06020000 (object does not exist in the object dictionary)".
class SdoError : public std::runtime_error {
 public:
  SdoError(const std::string& message, std::uint32_t abort_code)
      : std::runtime_error(message), abort_code_(abort_code) {}
  std::uint32_t abort_code() const { return abort_code_; }

 private:
  std::uint32_t abort_code_;
};

/// "0x607D:02"
std::string to_string(ObjectAddress object);

/// Reads `object` of `node_id`. Throws SdoError.
std::vector<std::uint8_t> sdo_upload(BusPump& pump, int node_id, ObjectAddress object,
                                     double timeout_s);
/// Writes `data` to `object` of `node_id`. Throws SdoError.
void sdo_download(BusPump& pump, int node_id, ObjectAddress object,
                  std::span<const std::uint8_t> data, double timeout_s);

/// An unsigned value of `bytes` (1, 2 or 4) bytes, little-endian.
void sdo_write_value(BusPump& pump, int node_id, ObjectAddress object, std::uint32_t value,
                     std::size_t bytes, double timeout_s);
/// Reads an object of at most 4 bytes as an unsigned value (zero-extended). Throws SdoError when
/// the answer is longer than 4 bytes or empty.
std::uint32_t sdo_read_value(BusPump& pump, int node_id, ObjectAddress object, double timeout_s);

}  // namespace cambio::canopen
