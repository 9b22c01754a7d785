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
// expects it; one the drive does not have is not touched (a drive with one PDO each way fits).
// PDOs 3 and 4, which the layout never uses, are only invalidated (COB-ID bit 31), where the
// drive has them: a drive that ships them valid would otherwise answer every SYNC with them.

#include <array>
#include <vector>

#include "cambio/canopen/object_write.hpp"
#include "cambio/canopen/pdo_layout.hpp"

namespace cambio::canopen {

/// Which of CiA 301's four RPDOs and four TPDOs (its predefined connection set) a drive has: the
/// master asks it (an SDO read of each communication object's COB-ID) for the PDOs the layout
/// does not use.
struct PdoPresence {
  std::array<bool, 4> rpdos{true, true, true, true};
  std::array<bool, 4> tpdos{true, true, true, true};
};

/// The exact SDO writes that configure `layout` on `node_id`, in order.
std::vector<ObjectWrite> pdo_configuration_writes(int node_id, const PdoLayout& layout,
                                                  const PdoPresence& present = {});

}  // namespace cambio::canopen
