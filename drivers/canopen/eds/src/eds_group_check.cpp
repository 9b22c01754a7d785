#include "cambio/canopen/eds/eds_group_check.hpp"

#include <algorithm>
#include <set>
#include <utility>

#include "cambio/canopen/sdo_transfer.hpp"
#include "eds_group_problems.hpp"

namespace cambio::canopen::eds {

namespace {

std::string bits_text(const DataTypeInfo& type) {
  return std::string(type.name) + " (" + std::to_string(type.bits) + " bits)";
}

/// Where a missing or unfit object leaves the user: the rig setting that avoids it, or the drive.
std::string change_for(const ObjectPurpose& purpose, std::string_view unfit) {
  if (purpose.optional) {
    return "turn off " + purpose.rig_setting +
           " (then the master leaves it alone), or use a drive whose " + std::string(unfit);
  }
  return "use a drive whose " + std::string(unfit) + " (the master needs it whatever " +
         (purpose.rig_setting.empty() ? std::string("the rig says") : purpose.rig_setting + " is") +
         ")";
}

void check_limits(const EdsEntry& entry, const ObjectWrite& write, int node_id,
                  const ObjectPurpose& purpose, ProblemContext& context) {
  const DataTypeInfo& type = *entry.data_type;
  const std::int64_t value = as_type(static_cast<std::int64_t>(write.value), type);
  const auto outside = [&](const std::optional<EdsInteger>& limit, bool low) {
    if (!limit) return false;
    const std::int64_t bound = as_type(limit->evaluate(node_id), type);
    return low ? value < bound : value > bound;
  };
  if (!outside(entry.low_limit, true) && !outside(entry.high_limit, false)) return;
  const auto limit_text = [&](const std::optional<EdsInteger>& limit) {
    return limit ? std::to_string(as_type(limit->evaluate(node_id), type)) : std::string("-");
  };
  context.add(write.object,
              "the master writes " + std::to_string(value) + " (" + purpose.what +
                  "), outside LowLimit..HighLimit " + limit_text(entry.low_limit) + ".." +
                  limit_text(entry.high_limit),
              purpose.rig_setting.empty()
                  ? "use a drive that accepts the master's value"
                  : "change " + purpose.rig_setting + " so the value is within the limits");
}

void check_use(const ObjectUse& use, bool read_back, int node_id, const ObjectPurpose& purpose,
               ProblemContext& context) {
  const ObjectAddress object = use.access.object;
  const bool write = use.kind == ObjectUse::Kind::kWrite;
  const EdsEntry* entry = context.eds().find(object);
  if (entry == nullptr) {
    const EdsObject* parent = context.eds().find(object.index);
    context.add(object,
                (parent == nullptr ? "not in the EDS"
                                   : "[" + index_text(object.index) + "] has no sub-index " +
                                         std::to_string(object.subindex)) +
                    "; the master " + (write ? "writes" : "reads") + " it (" + purpose.what + ")",
                change_for(purpose, "EDS has it"));
    return;
  }
  const DataTypeInfo& type = *entry->data_type;
  if (write && !writable(entry->access)) {
    context.add(object,
                "AccessType " + std::string(to_string(entry->access)) + ": the master writes it (" +
                    purpose.what + ")",
                change_for(purpose, "object is writable"));
  }
  if (!write && !readable(entry->access)) {
    context.add(object,
                std::string("AccessType wo: the master reads it ") +
                    (read_back ? "back after writing it (" : "(") + purpose.what + ")",
                change_for(purpose, "object is readable"));
  }
  if (write && type.bits != 8 * use.access.bytes) {
    context.add(object,
                "DataType " + bits_text(type) + ", the master writes " +
                    std::to_string(8 * use.access.bytes) +
                    " bits (the drive aborts a length "
                    "mismatch, SDO abort 0x06070010)",
                change_for(purpose, "object is " + std::to_string(8 * use.access.bytes) + " bits"));
  }
  if (!write && (!type.is_integer() || type.bits < 8 || type.bits > 32)) {
    context.add(object, "DataType " + bits_text(type) + ": the master reads 8 to 32-bit integers",
                change_for(purpose, "object is an 8 to 32-bit integer"));
  }
  if (write && type.is_integer()) check_limits(*entry, use.access, node_id, purpose, context);
}

}  // namespace

std::string EdsProblem::to_string() const {
  std::string text = canopen::to_string(object) + " " + object_name;
  if (line > 0) text += " (line " + std::to_string(line) + ")";
  text += joints.size() == 1 ? ", joint " : ", joints ";
  for (std::size_t i = 0; i < joints.size(); ++i) text += (i > 0 ? ", " : "") + joints[i];
  return text + ": " + problem + "; " + change;
}

EdsGroupReport check_eds_for_group(const EdsFile& eds, const CanGroupView& view,
                                   std::optional<int> node_id) {
  EdsGroupReport report;
  std::set<std::pair<std::uint16_t, std::uint8_t>> used;
  std::vector<std::size_t> checked;
  for (std::size_t k = 0; k < view.joints.size(); ++k) {
    if (node_id && view.drives[k].node_id != *node_id) continue;
    checked.push_back(k);
    report.joints_checked.push_back(view.joints[k].name);
    ProblemContext context(eds, view.joints[k].name, report);
    std::set<std::pair<std::uint16_t, std::uint8_t>> written;
    for (const ObjectUse& use : master_object_uses(view, k)) {
      const std::pair key{use.access.object.index, use.access.object.subindex};
      used.insert(key);
      const bool read_back = use.kind == ObjectUse::Kind::kRead && written.contains(key);
      // A missing object is one problem, however often the master would use it.
      if (read_back && eds.find(use.access.object) == nullptr) continue;
      if (use.kind == ObjectUse::Kind::kWrite) written.insert(key);
      check_use(use, read_back, view.drives[k].node_id, object_purpose(use.access.object, view, k),
                context);
    }
    check_device_type(view, k, context);
    check_drive_modes(view, k, context);
  }
  if (!checked.empty()) {
    ProblemContext context(eds, report.joints_checked, report);
    check_pdo_layout(view, checked.front(), context, used);
  }
  report.objects_checked = static_cast<int>(used.size());
  return report;
}

}  // namespace cambio::canopen::eds
