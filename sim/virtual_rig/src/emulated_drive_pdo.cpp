// The emulated drive's PDOs: RPDOs applied on SYNC, TPDOs sent after it, and mappings checked
// and rebuilt as a master writes them over SDO (CiA 301 7.4.7, 7.5.2.35-38).
#include <algorithm>

#include "cambio/virtual_rig/emulated_drive.hpp"
#include "emulated_drive_detail.hpp"

namespace cambio::virtual_rig {

using namespace emulated_drive_detail;

void EmulatedDrive::handle_rpdo(int n, const hal::CanFrame& frame) noexcept {
  Pdo& pdo = rpdos_[static_cast<std::size_t>(n)];
  if (frame.length < pdo.bytes) {
    // CiA 301: a PDO shorter than its mapping is not processed; EMCY 0x8210 says so.
    ++counters_.malformed_frames;
    const std::uint8_t saved = static_cast<std::uint8_t>(error_register_->value);
    error_register_->value = saved | kErrorGeneric | kErrorCommunication;
    send_emergency(kEmcyPdoLength);
    error_register_->value = saved;
    return;
  }
  ++counters_.rpdos;
  if (pdo.transmission_type <= 240) {
    std::copy_n(frame.data.begin(), pdo.bytes, pdo.pending.begin());
    pdo.has_pending = true;
  } else {
    apply_rpdo(pdo, std::span<const std::uint8_t>(frame.data.data(), pdo.bytes));
  }
}

void EmulatedDrive::apply_rpdo(const Pdo& pdo, std::span<const std::uint8_t> data) noexcept {
  std::size_t offset = 0;
  for (std::size_t k = 0; k < pdo.count; ++k) {
    const MappedEntry& mapped = pdo.entries[k];
    const std::uint32_t raw = canopen::get_le(data, offset, mapped.bytes);
    offset += mapped.bytes;
    ObjectEntry& entry = *mapped.entry;
    if (&entry == mode_) {
      const auto mode = static_cast<std::int8_t>(raw);
      if (mode != 8 && mode != 9) continue;  // Not a mode this drive has: keep the old one.
      const bool changed = mode_->value != raw;
      entry.value = raw;
      if (changed && hal::is_enabled(drive_state_)) enter(drive_state_);
      continue;
    }
    entry.value = raw;
    if (&entry == controlword_) {
      on_controlword(static_cast<std::uint16_t>(raw));
    } else if (&entry == target_position_ || &entry == target_velocity_ ||
               &entry == velocity_offset_ || &entry == torque_offset_) {
      targets_written_ = targets_written_ || hal::is_enabled(drive_state_);
    }
  }
}

void EmulatedDrive::send_tpdos(std::int64_t now_ns) noexcept {
  for (Pdo& pdo : tpdos_) {
    if (!pdo.valid || pdo.count == 0) continue;
    if (pdo.transmission_type != 0 && ++pdo.sync_count < pdo.transmission_type) continue;
    pdo.sync_count = 0;
    hal::CanFrame frame;
    frame.id = pdo.cob_id;
    frame.length = static_cast<std::uint8_t>(pdo.bytes);
    std::size_t offset = 0;
    for (std::size_t k = 0; k < pdo.count; ++k) {
      canopen::put_le(frame.data, offset, pdo.entries[k].bytes, pdo.entries[k].entry->value);
      offset += pdo.entries[k].bytes;
    }
    if (pdo.transmission_type == 0 && pdo.sent_once &&
        std::equal(frame.data.begin(), frame.data.begin() + static_cast<long>(pdo.bytes),
                   pdo.last_sent.begin())) {
      continue;  // Acyclic synchronous: only when the data changed.
    }
    std::copy_n(frame.data.begin(), pdo.bytes, pdo.last_sent.begin());
    pdo.sent_once = true;
    if (tpdos_to_drop_ > 0) {
      --tpdos_to_drop_;
      ++counters_.tpdos_dropped;
      continue;
    }
    if (tpdos_to_delay_ > 0 && late_count_ < kMaxLateFrames) {
      --tpdos_to_delay_;
      ++counters_.tpdos_late;
      late_[late_count_++] = {frame, now_ns + tpdo_delay_ns_};
      continue;
    }
    send(frame);
    ++counters_.tpdos_sent;
  }
}

std::uint32_t EmulatedDrive::check_mapping(bool receive, std::uint32_t mapping) const noexcept {
  if (mapping == 0) return 0;  // An unused entry.
  const ObjectAddress object = canopen::mapped_object(mapping);
  const ObjectEntry* entry = dictionary_.find(object);
  if (entry == nullptr) return dictionary_.missing_code(object);
  if (!entry->pdo_mappable) return code(SdoAbortCode::kCannotMapToPdo);
  if (receive ? !writable(entry->access) : !readable(entry->access)) {
    return code(SdoAbortCode::kCannotMapToPdo);
  }
  // Whole objects only: the entry's length must be the object's.
  if (static_cast<std::size_t>(canopen::mapped_bits(mapping)) != 8 * size_of(entry->type)) {
    return code(SdoAbortCode::kCannotMapToPdo);
  }
  return 0;
}

std::uint32_t EmulatedDrive::check_pdo_write(ObjectAddress address,
                                             std::span<const std::uint8_t> data) const noexcept {
  const std::uint16_t index = address.index;
  const bool rpdo_comm = in(index, canopen::kRpdoCommunication);
  const bool tpdo_comm = in(index, canopen::kTpdoCommunication);
  const bool rpdo_map = in(index, canopen::kRpdoMapping);
  const bool tpdo_map = in(index, canopen::kTpdoMapping);
  if (!rpdo_comm && !tpdo_comm && !rpdo_map && !tpdo_map) return 0;
  const std::uint32_t value = canopen::get_le(data, 0, data.size());
  if (rpdo_comm || tpdo_comm) {
    if (address.subindex == 1) {
      const std::uint32_t current = dictionary_.get(address);
      if ((value & 0x2000'0000u) != 0) return code(SdoAbortCode::kInvalidValue);  // 29-bit ids.
      const bool valid_now = (current & canopen::kPdoCobIdInvalid) == 0;
      const bool valid_next = (value & canopen::kPdoCobIdInvalid) == 0;
      // CiA 301: a valid PDO's COB-ID cannot change; invalidate it first.
      if (valid_now && valid_next && (value & 0x7FFu) != (current & 0x7FFu)) {
        return code(SdoAbortCode::kInvalidValue);
      }
      if (valid_next && (value & 0x7FFu) == 0) return code(SdoAbortCode::kInvalidValue);
    } else if (address.subindex == 2) {
      // RPDO: synchronous 0..240 or event 254/255. TPDO: synchronous only (1..240, 0 acyclic).
      const bool ok = value <= 240 || (rpdo_comm && value >= 254);
      if (!ok) return code(SdoAbortCode::kInvalidValue);
    }
    return 0;
  }
  const auto comm_index = static_cast<std::uint16_t>(
      index - (rpdo_map ? canopen::kRpdoMapping : canopen::kTpdoMapping) +
      (rpdo_map ? canopen::kRpdoCommunication : canopen::kTpdoCommunication));
  // CiA 301 §7.5.2.36: the mapping changes only while the PDO is invalid and, for the entries,
  // while sub 0 is 0.
  if ((dictionary_.get({comm_index, 1}) & canopen::kPdoCobIdInvalid) == 0) {
    return code(SdoAbortCode::kCannotTransferDeviceState);
  }
  if (address.subindex != 0) {
    if (dictionary_.get({index, 0}) != 0) return code(SdoAbortCode::kCannotTransferDeviceState);
    return check_mapping(rpdo_map, value);
  }
  int bits = 0;
  for (std::uint32_t k = 1; k <= value; ++k) {
    const std::uint32_t entry = dictionary_.get({index, static_cast<std::uint8_t>(k)});
    if (entry == 0) return code(SdoAbortCode::kCannotMapToPdo);
    if (const std::uint32_t abort = check_mapping(rpdo_map, entry)) return abort;
    bits += canopen::mapped_bits(entry);
  }
  if (bits > 64) return code(SdoAbortCode::kPdoLengthExceeded);
  return 0;
}

void EmulatedDrive::rebuild_pdos() noexcept {
  const auto build = [this](std::array<Pdo, kPdoCount>& pdos, std::uint16_t comm,
                            std::uint16_t map) {
    for (int n = 0; n < kPdoCount; ++n) {
      Pdo& pdo = pdos[static_cast<std::size_t>(n)];
      pdo = Pdo{};
      const auto comm_index = static_cast<std::uint16_t>(comm + n);
      const auto map_index = static_cast<std::uint16_t>(map + n);
      const std::uint32_t cob_id = dictionary_.get({comm_index, 1});
      pdo.valid = (cob_id & canopen::kPdoCobIdInvalid) == 0;
      pdo.cob_id = cob_id & 0x7FFu;
      pdo.transmission_type = static_cast<std::uint8_t>(dictionary_.get({comm_index, 2}));
      const std::uint32_t count = dictionary_.get({map_index, 0});
      for (std::uint32_t k = 1; k <= count && k <= kMaxMappedObjects; ++k) {
        const std::uint32_t mapping = dictionary_.get({map_index, static_cast<std::uint8_t>(k)});
        ObjectEntry* entry = dictionary_.find(canopen::mapped_object(mapping));
        if (entry == nullptr) break;  // Checked when written; a default never lacks its object.
        const auto bytes = static_cast<std::size_t>(canopen::mapped_bits(mapping)) / 8;
        if (pdo.bytes + bytes > 8) break;
        pdo.entries[pdo.count++] = {entry, bytes};
        pdo.bytes += bytes;
      }
    }
  };
  build(rpdos_, canopen::kRpdoCommunication, canopen::kRpdoMapping);
  build(tpdos_, canopen::kTpdoCommunication, canopen::kTpdoMapping);
}

}  // namespace cambio::virtual_rig
