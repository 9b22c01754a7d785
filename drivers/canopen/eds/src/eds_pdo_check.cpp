// The PDO layout (pdo_layout.hpp) against the drive: how many RPDOs and TPDOs it has
// ([DeviceInfo] NrOfRXPDO / NrOfTXPDO, else the communication objects present), how many entries
// each mapping object (0x16xx / 0x1Axx) holds (its sub-indices 1..n, bounded by sub 0's
// HighLimit when given), and whether each mapped object is mappable, of the mapped size and
// readable (TPDO) or writable (RPDO).
#include <algorithm>
#include <array>

#include "eds_group_problems.hpp"

namespace cambio::canopen::eds {

namespace {

struct Direction {
  const std::array<PdoMapping, 2>& pdos;
  std::optional<int> declared;
  std::uint16_t communication;
  std::uint16_t mapping;
  std::string_view name;       ///< "RPDO"
  std::string_view count_key;  ///< "NrOfRXPDO"
  bool receive;                ///< The drive receives it (RPDO): mapped objects are written.
};

/// How many entries the mapping object can hold, or -1 when it is not in the EDS.
int mapping_capacity(const EdsObject* mapping) {
  if (mapping == nullptr) return -1;
  const auto entries =
      static_cast<int>(std::count_if(mapping->entries.begin(), mapping->entries.end(),
                                     [](const auto& entry) { return entry.first >= 1; }));
  const auto sub0 = mapping->entries.find(0);
  if (sub0 == mapping->entries.end() || !sub0->second.high_limit) return entries;
  return static_cast<int>(std::clamp<std::int64_t>(sub0->second.high_limit->constant, 0, entries));
}

void check_mapped_object(const MappedObject& mapped, const Direction& direction, int n,
                         const CanGroupView& view, std::size_t joint, ProblemContext& context) {
  const ObjectPurpose purpose = object_purpose(mapped.object, view, joint);
  const std::string where = std::string(direction.name) + std::to_string(n);
  const std::string change =
      purpose.optional ? "turn off " + purpose.rig_setting + ", or use a drive that maps it"
                       : "use a drive that maps it (the master maps it whatever the rig says)";
  const EdsEntry* entry = context.eds().find(mapped.object);
  if (entry == nullptr) {
    context.add(mapped.object, "not in the EDS; the master maps it in " + where, change);
    return;
  }
  if (!entry->pdo_mappable) {
    context.add(mapped.object, "PDOMapping=0; the master maps it in " + where, change);
  }
  if (entry->data_type->bits != mapped.bits) {
    context.add(mapped.object,
                "DataType " + std::string(entry->data_type->name) + " is " +
                    std::to_string(entry->data_type->bits) + " bits; the master maps " +
                    std::to_string(mapped.bits) + " bits in " + where,
                change);
  }
  if (direction.receive ? !writable(entry->access) : !readable(entry->access)) {
    context.add(mapped.object,
                "AccessType " + std::string(to_string(entry->access)) + "; the master maps it in " +
                    where + (direction.receive ? ", which writes it" : ", which reads it"),
                change);
  }
}

void check_direction(const Direction& direction, const CanGroupView& view, std::size_t joint,
                     ProblemContext& context,
                     std::set<std::pair<std::uint16_t, std::uint8_t>>& used) {
  int needed = 0;
  for (int n = 1; n <= static_cast<int>(direction.pdos.size()); ++n) {
    if (!direction.pdos[static_cast<std::size_t>(n - 1)].empty()) needed = n;
  }
  int available = 0;
  if (direction.declared) {
    available = *direction.declared;
  } else {
    for (int n = 0;
         n < 0x200 &&
         context.eds().find(static_cast<std::uint16_t>(direction.communication + n)) != nullptr;
         ++n) {
      ++available;
    }
    context.note("[DeviceInfo] gives no " + std::string(direction.count_key) + ": counted " +
                 std::to_string(available) + " " + std::string(direction.name) +
                 " communication objects instead");
  }
  if (needed > available) {
    const std::string setting = direction.receive ? "feedforward" : "feedback";
    context.add({static_cast<std::uint16_t>(direction.mapping + needed - 1), 0},
                "the layout needs " + std::string(direction.name) + "1.." +
                    std::string(direction.name) + std::to_string(needed) + ", the drive has " +
                    std::to_string(available) + " (" + std::string(direction.count_key) + ")",
                "turn off groups." + view.group.name + ".can." + setting +
                    ", or use a drive with more " + std::string(direction.name) + "s");
  }
  for (int n = 1; n <= needed; ++n) {
    const PdoMapping& mapping = direction.pdos[static_cast<std::size_t>(n - 1)];
    const auto mapping_index = static_cast<std::uint16_t>(direction.mapping + n - 1);
    const int capacity = mapping_capacity(context.eds().find(mapping_index));
    if (capacity >= 0 && static_cast<int>(mapping.count) > capacity) {
      context.add({mapping_index, 0},
                  "the layout maps " + std::to_string(mapping.count) + " objects in " +
                      std::string(direction.name) + std::to_string(n) + ", the drive holds " +
                      std::to_string(capacity),
                  "map fewer objects (groups." + view.group.name +
                      ".can.feedforward / .feedback), or use a drive with more mapping entries");
    }
    for (std::size_t i = 0; i < mapping.count; ++i) {
      used.insert({mapping.entries[i].object.index, mapping.entries[i].object.subindex});
      check_mapped_object(mapping.entries[i], direction, n, view, joint, context);
    }
  }
}

}  // namespace

void check_pdo_layout(const CanGroupView& view, std::size_t joint, ProblemContext& context,
                      std::set<std::pair<std::uint16_t, std::uint8_t>>& used) {
  const PdoLayout layout = master_pdo_layout(view);
  const EdsFile& eds = context.eds();
  check_direction(
      {layout.rpdos, eds.rx_pdos, kRpdoCommunication, kRpdoMapping, "RPDO", "NrOfRXPDO", true},
      view, joint, context, used);
  check_direction(
      {layout.tpdos, eds.tx_pdos, kTpdoCommunication, kTpdoMapping, "TPDO", "NrOfTXPDO", false},
      view, joint, context, used);
}

}  // namespace cambio::canopen::eds
