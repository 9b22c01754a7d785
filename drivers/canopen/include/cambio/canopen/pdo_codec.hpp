#pragma once

// PDO pack/unpack on the loop side: the objects a PdoMapping lists, in order, little-endian,
// back to back (CiA 301 §7.2.2). Generic over who reads the values, so the master (targets out,
// feedback in) and an emulated drive (the other way round) share one codec. Header-only, no
// allocation.

#include <cstdint>

#include "cambio/canopen/cia402.hpp"
#include "cambio/canopen/pdo_layout.hpp"
#include "cambio/hal/can_bus.hpp"

namespace cambio::canopen {

/// Fills `frame` (id and length included) with `mapping`'s objects, each taken from
/// `value_of(ObjectAddress) -> std::uint32_t` (raw bits). Mappings whose sizes are not whole
/// bytes are not produced by pdo_layout() and are not supported.
template <class ValueOf>
void pack_pdo(const PdoMapping& mapping, std::uint32_t cob_id, ValueOf&& value_of,
              hal::CanFrame& frame) {
  frame.id = cob_id;
  frame.extended_id = false;
  frame.remote_request = false;
  frame.error_frame = false;
  frame.fd = false;
  frame.bit_rate_switch = false;
  std::size_t offset = 0;
  for (std::size_t i = 0; i < mapping.count; ++i) {
    const std::size_t bytes = static_cast<std::size_t>(mapping.entries[i].bits) / 8;
    put_le(frame.data, offset, bytes, value_of(mapping.entries[i].object));
    offset += bytes;
  }
  frame.length = static_cast<std::uint8_t>(offset);
}

/// Hands each mapped object of `frame` to `store(ObjectAddress, raw bits, bytes)`. Returns false,
/// storing nothing, when the frame's length is not the mapping's (a malformed PDO).
template <class Store>
bool unpack_pdo(const PdoMapping& mapping, const hal::CanFrame& frame, Store&& store) {
  if (frame.remote_request || frame.extended_id || frame.fd ||
      static_cast<int>(frame.length) != mapping.bytes()) {
    return false;
  }
  std::size_t offset = 0;
  for (std::size_t i = 0; i < mapping.count; ++i) {
    const std::size_t bytes = static_cast<std::size_t>(mapping.entries[i].bits) / 8;
    store(mapping.entries[i].object, get_le(frame.data, offset, bytes), bytes);
    offset += bytes;
  }
  return true;
}

/// What the master sends a CiA 402 drive each cycle (drive units).
struct DriveTargets {
  std::uint16_t controlword = 0;
  std::int32_t target_position_counts = 0;
  std::int32_t target_velocity_counts_s = 0;
  std::int32_t velocity_offset_counts_s = 0;
  std::int16_t torque_offset_per_mille = 0;  ///< 1/1000 of rated torque.
};

/// What a CiA 402 drive reports (drive units).
struct DriveFeedback {
  std::uint16_t statusword = 0;
  std::int32_t position_counts = 0;
  std::int32_t velocity_counts_s = 0;
  std::int16_t torque_per_mille = 0;
};

/// The raw bits of a target object (0 for an object a master never maps).
constexpr std::uint32_t raw_target(const DriveTargets& targets, ObjectAddress object) {
  if (object == cia402::kControlword) return targets.controlword;
  if (object == cia402::kTargetPosition) {
    return static_cast<std::uint32_t>(targets.target_position_counts);
  }
  if (object == cia402::kTargetVelocity) {
    return static_cast<std::uint32_t>(targets.target_velocity_counts_s);
  }
  if (object == cia402::kVelocityOffset) {
    return static_cast<std::uint32_t>(targets.velocity_offset_counts_s);
  }
  if (object == cia402::kTorqueOffset) {
    return static_cast<std::uint16_t>(targets.torque_offset_per_mille);
  }
  return 0;
}

/// Stores one feedback object's raw bits into `feedback` (objects it does not know are ignored).
constexpr void store_feedback(DriveFeedback& feedback, ObjectAddress object, std::uint32_t raw,
                              std::size_t bytes) {
  if (object == cia402::kStatusword) {
    feedback.statusword = static_cast<std::uint16_t>(raw);
  } else if (object == cia402::kPositionActualValue) {
    feedback.position_counts = sign_extend(raw, bytes);
  } else if (object == cia402::kVelocityActualValue) {
    feedback.velocity_counts_s = sign_extend(raw, bytes);
  } else if (object == cia402::kTorqueActualValue) {
    feedback.torque_per_mille = static_cast<std::int16_t>(sign_extend(raw, bytes));
  }
}

}  // namespace cambio::canopen
