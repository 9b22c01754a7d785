#pragma once

// Which objects a CiA 402 drive's PDOs carry, decided once from the group's settings and used by
// everyone who must agree on it: the master (what it maps over SDO and packs each cycle), the
// emulated drives (they apply whatever the master maps), and the rig loader's bus-load model
// (it counts the bytes actually mapped). Header-only, no allocation.
//
//   RPDO1  controlword (16) + target position (32, CSP) or target velocity (32, CSV)
//   RPDO2  velocity offset (32, CSP only) + torque offset (16)       only when feed-forward is on
//   TPDO1  statusword (16) + position actual value (32)
//   TPDO2  velocity actual value (32) + torque actual value (16)     only when feedback is on

#include <array>
#include <cstddef>

#include "cambio/canopen/can_rig.hpp"
#include "cambio/canopen/cia402.hpp"
#include "cambio/hal/joint_group.hpp"

namespace cambio::canopen {

struct MappedObject {
  ObjectAddress object;
  int bits = 0;
};

/// One PDO's mapping: up to 8 objects (CiA 301 allows 64, a classic frame's 8 bytes bound it).
struct PdoMapping {
  std::array<MappedObject, 8> entries{};
  std::size_t count = 0;

  void add(ObjectAddress object, int bits) { entries[count++] = {object, bits}; }
  int bytes() const {
    int bits = 0;
    for (std::size_t i = 0; i < count; ++i) bits += entries[i].bits;
    return (bits + 7) / 8;
  }
  bool empty() const { return count == 0; }
};

struct PdoLayout {
  std::array<PdoMapping, 2> rpdos{};  ///< RPDO1, RPDO2 (master -> drive).
  std::array<PdoMapping, 2> tpdos{};  ///< TPDO1, TPDO2 (drive -> master).
};

inline PdoLayout pdo_layout(hal::CommandMode mode, const CanGroupSettings& settings) {
  PdoLayout layout;
  layout.rpdos[0].add(cia402::kControlword, 16);
  layout.rpdos[0].add(
      mode == hal::CommandMode::kPosition ? cia402::kTargetPosition : cia402::kTargetVelocity, 32);
  if (settings.velocity_feedforward && mode == hal::CommandMode::kPosition) {
    layout.rpdos[1].add(cia402::kVelocityOffset, 32);
  }
  if (settings.effort_feedforward) layout.rpdos[1].add(cia402::kTorqueOffset, 16);
  layout.tpdos[0].add(cia402::kStatusword, 16);
  layout.tpdos[0].add(cia402::kPositionActualValue, 32);
  if (settings.velocity_feedback) layout.tpdos[1].add(cia402::kVelocityActualValue, 32);
  if (settings.effort_feedback) layout.tpdos[1].add(cia402::kTorqueActualValue, 16);
  return layout;
}

}  // namespace cambio::canopen
