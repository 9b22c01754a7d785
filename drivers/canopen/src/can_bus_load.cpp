#include "cambio/canopen/can_bus_load.hpp"

#include "cambio/canopen/pdo_layout.hpp"

namespace cambio::canopen {

int can_frame_worst_case_bits(int data_bytes) {
  const int stuffed_bits = 34 + 8 * data_bytes;  // SOF through CRC: the bits stuffing applies to.
  return 47 + 8 * data_bytes + (stuffed_bits - 1) / 4;
}

CanBusLoad can_bus_load(const hal::HardwareInfo& hardware, const CanRigInfo& can_rig,
                        const CanBusInfo& bus, std::string_view backend) {
  CanBusLoad result;
  if (bus.bitrate_bit_s <= 0) return result;
  for (const auto& group : hardware.groups) {
    const CanGroupInfo* can_group = can_rig.find_group(group.name);
    if (group.backend != backend || can_group == nullptr || can_group->bus != bus.name) continue;
    CanGroupLoad load;
    load.group = group.name;
    load.rate_hz = group.rate_hz;
    for (const auto& joint_name : group.joints) {
      const JointDriveInfo* drive = can_rig.find_drive(joint_name);
      // A joint without a drive is the check's to report; it puts nothing on the bus.
      if (drive == nullptr) continue;
      const PdoLayout layout = pdo_layout(drive->mode, can_group->settings);
      for (const auto* pdos : {&layout.rpdos, &layout.tpdos}) {
        for (const auto& pdo : *pdos) {
          if (!pdo.empty()) load.bits_per_cycle += can_frame_worst_case_bits(pdo.bytes());
        }
      }
      ++load.drives;
    }
    load.bits_per_cycle += can_frame_worst_case_bits(0);  // The SYNC.
    load.heartbeat_bit_s =
        load.drives * can_frame_worst_case_bits(1) / can_group->settings.heartbeat_period_s;
    load.bit_s = load.bits_per_cycle * load.rate_hz + load.heartbeat_bit_s;
    result.bit_s += load.bit_s;
    result.groups.push_back(std::move(load));
  }
  result.load = result.bit_s / static_cast<double>(bus.bitrate_bit_s);
  return result;
}

}  // namespace cambio::canopen
