#include "cambio/canopen/object_write.hpp"

#include <array>
#include <cstdio>

#include "cambio/canopen/sdo_transfer.hpp"

namespace cambio::canopen {

std::string describe_value(const ObjectWrite& write, std::uint32_t raw) {
  const std::uint32_t mask = write.bytes >= 4 ? 0xFFFF'FFFFu : (1u << (8 * write.bytes)) - 1u;
  raw &= mask;
  std::array<char, 48> text{};
  if (write.is_signed) {
    std::snprintf(text.data(), text.size(), "%d (0x%0*X)", sign_extend(raw, write.bytes),
                  2 * write.bytes, raw);
  } else {
    std::snprintf(text.data(), text.size(), "%u (0x%0*X)", raw, 2 * write.bytes, raw);
  }
  return text.data();
}

void write_objects(BusPump& pump, int node_id, std::span<const ObjectWrite> writes,
                   double timeout_s) {
  for (const ObjectWrite& write : writes) {
    sdo_write_value(pump, node_id, write.object, write.value, write.bytes, timeout_s);
  }
}

std::vector<std::string> verify_objects(BusPump& pump, int node_id, const std::string& what,
                                        std::span<const ObjectWrite> writes, double timeout_s) {
  std::vector<std::string> mismatches;
  for (std::size_t i = 0; i < writes.size(); ++i) {
    const ObjectWrite& write = writes[i];
    bool overwritten_later = false;
    for (std::size_t j = i + 1; j < writes.size(); ++j) {
      overwritten_later = overwritten_later || writes[j].object == write.object;
    }
    if (!write.verify || overwritten_later) continue;
    const std::uint32_t mask = write.bytes >= 4 ? 0xFFFF'FFFFu : (1u << (8 * write.bytes)) - 1u;
    const std::uint32_t read = sdo_read_value(pump, node_id, write.object, timeout_s);
    if ((read & mask) != (write.value & mask)) {
      mismatches.push_back("node " + std::to_string(node_id) + " (" + what + "): object " +
                           to_string(write.object) + " written " +
                           describe_value(write, write.value) + ", read back " +
                           describe_value(write, read));
    }
  }
  return mismatches;
}

}  // namespace cambio::canopen
