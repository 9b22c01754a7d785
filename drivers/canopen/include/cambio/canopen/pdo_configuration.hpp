#pragma once

// PDO configuration over SDO as CiA 301 §7.5.2.35-38 prescribes, for the layout pdo_layout.hpp
// decides. For each PDO (RPDO1, RPDO2, TPDO1, TPDO2):
//   1. COB-ID (0x1400+n-1 / 0x1800+n-1 sub 1) with bit 31 set: the PDO is invalid while mapped
//   2. mapping count (0x1600+n-1 / 0x1A00+n-1 sub 0) = 0
//   3. mapping entries (sub 1..k) = index << 16 | subindex << 8 | bits
//   4. mapping count = k
//   5. transmission type (sub 2) = 1: synchronous, every SYNC
//   6. COB-ID without bit 31: valid again (TPDOs also set bit 30, no RTR)
// A PDO the layout leaves empty is left invalid with no entries, so the drive never sends or
// expects it.

#include <vector>

#include "cambio/canopen/object_write.hpp"
#include "cambio/canopen/pdo_layout.hpp"

namespace cambio::canopen {

/// The exact SDO writes that configure `layout` on `node_id`, in order.
std::vector<ObjectWrite> pdo_configuration_writes(int node_id, const PdoLayout& layout);

}  // namespace cambio::canopen
