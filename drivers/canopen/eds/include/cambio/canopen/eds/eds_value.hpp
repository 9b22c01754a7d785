#pragma once

// Numbers as CiA 306 §4.6.3 writes them: decimal, hexadecimal (0x prefix) or octal (leading 0),
// a leading '-' for negative values, and the $NODEID term a vendor adds to node-dependent
// defaults (`$NODEID+0x180`, `0x80000200 + $NODEID`), evaluated for one node id.

#include <cstdint>
#include <optional>
#include <string_view>

namespace cambio::canopen::eds {

struct DataTypeInfo;

/// constant + node_id_terms * node id. The constant holds a value's bits: UNSIGNED64 values above
/// INT64_MAX wrap to negative numbers (two's complement), as the drive stores them.
struct EdsInteger {
  std::int64_t constant = 0;
  int node_id_terms = 0;  ///< How many $NODEID terms (minus those subtracted).

  bool depends_on_node_id() const { return node_id_terms != 0; }
  /// The value for `node_id`; wraps like the drive's own arithmetic would.
  std::int64_t evaluate(int node_id) const {
    return static_cast<std::int64_t>(static_cast<std::uint64_t>(constant) +
                                     static_cast<std::uint64_t>(node_id_terms) *
                                         static_cast<std::uint64_t>(node_id));
  }
};

/// `text` without the white space (spaces, tabs, CR) at either end.
std::string_view trim(std::string_view text);

/// A plain whole number (no sign, no $NODEID), or nullopt: for keys like SubNumber, DataType.
std::optional<std::uint64_t> parse_unsigned(std::string_view text);

/// A sum of numbers and $NODEID terms joined by '+' or '-', spaces allowed around each; nullopt
/// when it is anything else or overflows 64 bits.
std::optional<EdsInteger> parse_integer(std::string_view text);

/// Whether `value` (raw bits) is representable in `type`: an INTEGERn takes -2^(n-1) .. 2^n - 1
/// (a hex literal of its raw bits is common), an UNSIGNEDn 0 .. 2^n - 1.
bool fits(std::int64_t value, const DataTypeInfo& type);

/// `value` as the drive reads it: the low bits of `type`, sign-extended for INTEGERn.
std::int64_t as_type(std::int64_t value, const DataTypeInfo& type);

}  // namespace cambio::canopen::eds
