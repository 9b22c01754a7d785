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

std::vector<ObjectWrite> pdo_configuration_writes(int node_id, const PdoLayout& layout,
                                                  const PdoPresence& present) {
  std::vector<ObjectWrite> writes;
  const auto configure = [&](bool receive, int n) {
    const auto offset = static_cast<std::uint16_t>(n - 1);
    const auto k = static_cast<std::size_t>(n - 1);
    const auto& mappings = receive ? layout.rpdos : layout.tpdos;
    const PdoMapping unused{};
    const PdoMapping& mapping = k < mappings.size() ? mappings[k] : unused;
    if (mapping.empty() && !(receive ? present.rpdos[k] : present.tpdos[k])) return;
    const auto communication =
        static_cast<std::uint16_t>((receive ? kRpdoCommunication : kTpdoCommunication) + offset);
    const std::uint32_t cob_id = receive ? rpdo_cob_id(n, node_id) : tpdo_cob_id(n, node_id);
    const std::uint32_t flags = receive ? 0u : kPdoCobIdNoRtr;
    if (k >= mappings.size()) {
      writes.push_back({ObjectAddress{communication, 1}, cob_id | flags | kPdoCobIdInvalid, 4});
      return;
    }
    configure_pdo(writes, communication,
                  static_cast<std::uint16_t>((receive ? kRpdoMapping : kTpdoMapping) + offset),
                  cob_id, flags, mapping);
  };
  for (int n = 1; n <= 4; ++n) configure(true, n);
  for (int n = 1; n <= 4; ++n) configure(false, n);
  return writes;
}

}  // namespace cambio::canopen
