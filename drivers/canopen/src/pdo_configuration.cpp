#include "cambio/canopen/pdo_configuration.hpp"

namespace cambio::canopen {

namespace {

void configure_pdo(std::vector<ObjectWrite>& writes, std::uint16_t communication,
                   std::uint16_t mapping_index, std::uint32_t cob_id, std::uint32_t valid_flags,
                   const PdoMapping& mapping) {
  const ObjectAddress cob_id_object{communication, 1};
  const ObjectAddress count_object{mapping_index, 0};
  writes.push_back({cob_id_object, cob_id | valid_flags | kPdoCobIdInvalid, 4});
  writes.push_back({count_object, 0, 1});
  if (mapping.empty()) return;
  for (std::size_t i = 0; i < mapping.count; ++i) {
    writes.push_back({ObjectAddress{mapping_index, static_cast<std::uint8_t>(i + 1)},
                      pdo_mapping_entry(mapping.entries[i].object, mapping.entries[i].bits), 4});
  }
  writes.push_back({count_object, static_cast<std::uint32_t>(mapping.count), 1});
  writes.push_back({ObjectAddress{communication, 2}, kTransmissionSyncEvery, 1});
  writes.push_back({cob_id_object, cob_id | valid_flags, 4});
}

}  // namespace

std::vector<ObjectWrite> pdo_configuration_writes(int node_id, const PdoLayout& layout) {
  std::vector<ObjectWrite> writes;
  for (int n = 1; n <= static_cast<int>(layout.rpdos.size()); ++n) {
    const auto offset = static_cast<std::uint16_t>(n - 1);
    configure_pdo(writes, static_cast<std::uint16_t>(kRpdoCommunication + offset),
                  static_cast<std::uint16_t>(kRpdoMapping + offset), rpdo_cob_id(n, node_id), 0,
                  layout.rpdos[static_cast<std::size_t>(n - 1)]);
  }
  for (int n = 1; n <= static_cast<int>(layout.tpdos.size()); ++n) {
    const auto offset = static_cast<std::uint16_t>(n - 1);
    configure_pdo(writes, static_cast<std::uint16_t>(kTpdoCommunication + offset),
                  static_cast<std::uint16_t>(kTpdoMapping + offset), tpdo_cob_id(n, node_id),
                  kPdoCobIdNoRtr, layout.tpdos[static_cast<std::size_t>(n - 1)]);
  }
  return writes;
}

}  // namespace cambio::canopen
