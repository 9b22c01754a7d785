#pragma once

// A value a master writes to a drive's object dictionary at configure time, and the write-then-
// read-back that proves the drive took it (drive parameters, PDO configuration).

#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include "cambio/canopen/bus_pump.hpp"
#include "cambio/canopen/protocol.hpp"

namespace cambio::canopen {

struct ObjectWrite {
  ObjectAddress object;
  std::uint32_t value = 0;  ///< The raw bits (two's complement for signed types).
  std::uint8_t bytes = 4;   ///< 1, 2 or 4.
  bool is_signed = false;   ///< INTEGERn: shown signed in messages.
  /// Written but not read back: a value the drive changes on its own.
  bool verify = true;

  friend bool operator==(const ObjectWrite&, const ObjectWrite&) = default;
};

/// The value as a message shows it: decimal (signed where the type is) and hex.
std::string describe_value(const ObjectWrite& write, std::uint32_t raw);

/// Writes every entry in order over SDO (throws SdoError naming node and object).
void write_objects(BusPump& pump, int node_id, std::span<const ObjectWrite> writes,
                   double timeout_s);

/// Reads back the final value of every object written (the last write to each address, when
/// marked verify) and returns one message per mismatch, each naming the node, `what` (e.g.
/// "joint 'pan'"), the object index:subindex, the value written and the value read. Throws
/// SdoError when a read fails.
std::vector<std::string> verify_objects(BusPump& pump, int node_id, const std::string& what,
                                        std::span<const ObjectWrite> writes, double timeout_s);

}  // namespace cambio::canopen
