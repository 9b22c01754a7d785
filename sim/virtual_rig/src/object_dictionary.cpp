#include "cambio/virtual_rig/object_dictionary.hpp"

#include <algorithm>
#include <stdexcept>
#include <utility>

namespace cambio::virtual_rig {

namespace {

using canopen::ObjectAddress;
using canopen::SdoAbortCode;

constexpr std::uint32_t code(SdoAbortCode abort) {
  return static_cast<std::uint32_t>(abort);
}

bool before(const ObjectEntry& entry, ObjectAddress address) {
  return entry.address.index != address.index ? entry.address.index < address.index
                                              : entry.address.subindex < address.subindex;
}

void type_range(DataType type, std::int64_t& low, std::int64_t& high) {
  switch (type) {
    case DataType::kBoolean:
      low = 0, high = 1;
      return;
    case DataType::kInteger8:
      low = INT8_MIN, high = INT8_MAX;
      return;
    case DataType::kInteger16:
      low = INT16_MIN, high = INT16_MAX;
      return;
    case DataType::kInteger32:
      low = INT32_MIN, high = INT32_MAX;
      return;
    case DataType::kUnsigned8:
      low = 0, high = UINT8_MAX;
      return;
    case DataType::kUnsigned16:
      low = 0, high = UINT16_MAX;
      return;
    case DataType::kUnsigned32:
      low = 0, high = UINT32_MAX;
      return;
    case DataType::kVisibleString:
      low = 0, high = 0;
      return;
  }
}

}  // namespace

ObjectEntry& ObjectDictionary::add(ObjectAddress address, std::string_view name, DataType type,
                                   Access access, std::uint32_t default_value, bool pdo_mappable) {
  if (finalised_) throw std::logic_error("object dictionary: add() after finalise()");
  for (const auto& entry : entries_) {
    if (entry.address == address) throw std::logic_error("object dictionary: duplicate entry");
  }
  ObjectEntry entry;
  entry.address = address;
  entry.name = name;
  entry.type = type;
  entry.access = access;
  entry.pdo_mappable = pdo_mappable;
  type_range(type, entry.low, entry.high);
  entry.value = default_value;
  entry.default_value = default_value;
  entries_.push_back(std::move(entry));
  return entries_.back();
}

ObjectEntry& ObjectDictionary::add_string(ObjectAddress address, std::string_view name,
                                          std::string text) {
  ObjectEntry& entry = add(address, name, DataType::kVisibleString, Access::kConst, 0);
  entry.text = std::move(text);
  return entry;
}

void ObjectDictionary::finalise() {
  std::sort(entries_.begin(), entries_.end(),
            [](const ObjectEntry& a, const ObjectEntry& b) { return before(a, b.address); });
  finalised_ = true;
}

ObjectEntry* ObjectDictionary::find(ObjectAddress address) noexcept {
  return const_cast<ObjectEntry*>(std::as_const(*this).find(address));
}

const ObjectEntry* ObjectDictionary::find(ObjectAddress address) const noexcept {
  const auto it = std::lower_bound(entries_.begin(), entries_.end(), address, before);
  return it != entries_.end() && it->address == address ? &*it : nullptr;
}

bool ObjectDictionary::has_index(std::uint16_t index) const noexcept {
  const auto it =
      std::lower_bound(entries_.begin(), entries_.end(), ObjectAddress{index, 0}, before);
  return it != entries_.end() && it->address.index == index;
}

std::uint32_t ObjectDictionary::missing_code(ObjectAddress address) const noexcept {
  if (find(address) != nullptr) return 0;
  return has_index(address.index) ? code(SdoAbortCode::kSubindexDoesNotExist)
                                  : code(SdoAbortCode::kObjectDoesNotExist);
}

std::uint32_t ObjectDictionary::read(ObjectAddress address, std::span<std::uint8_t> out,
                                     std::size_t& size) const noexcept {
  const ObjectEntry* entry = find(address);
  if (entry == nullptr) return missing_code(address);
  if (!readable(entry->access)) return code(SdoAbortCode::kWriteOnly);
  size = entry->size();
  if (size > out.size()) return code(SdoAbortCode::kOutOfMemory);
  if (entry->type == DataType::kVisibleString) {
    std::copy(entry->text.begin(), entry->text.end(), out.begin());
  } else {
    canopen::put_le(out, 0, size, entry->value);
  }
  return 0;
}

std::uint32_t ObjectDictionary::check_write(ObjectAddress address,
                                            std::span<const std::uint8_t> data) const noexcept {
  const ObjectEntry* entry = find(address);
  if (entry == nullptr) return missing_code(address);
  if (!writable(entry->access)) return code(SdoAbortCode::kReadOnly);
  const std::size_t size = size_of(entry->type);
  if (size == 0) return code(SdoAbortCode::kReadOnly);  // Strings are constant here.
  if (data.size() > size) return code(SdoAbortCode::kLengthTooHigh);
  if (data.size() < size) return code(SdoAbortCode::kLengthTooLow);
  const std::uint32_t raw = canopen::get_le(data, 0, size);
  const std::int64_t value =
      is_signed(entry->type) ? canopen::sign_extend(raw, size) : static_cast<std::int64_t>(raw);
  if (value > entry->high) return code(SdoAbortCode::kValueTooHigh);
  if (value < entry->low) return code(SdoAbortCode::kValueTooLow);
  return 0;
}

std::uint32_t ObjectDictionary::write(ObjectAddress address,
                                      std::span<const std::uint8_t> data) noexcept {
  const std::uint32_t abort = check_write(address, data);
  if (abort != 0) return abort;
  ObjectEntry* entry = find(address);
  entry->value = canopen::get_le(data, 0, size_of(entry->type));
  return 0;
}

void ObjectDictionary::set(ObjectAddress address, std::uint32_t value) noexcept {
  ObjectEntry* entry = find(address);
  if (entry == nullptr) return;
  const std::size_t size = size_of(entry->type);
  entry->value = size >= 4 ? value : value & ((1u << (8 * size)) - 1u);
}

std::uint32_t ObjectDictionary::get(ObjectAddress address) const noexcept {
  const ObjectEntry* entry = find(address);
  return entry != nullptr ? entry->value : 0;
}

std::int32_t ObjectDictionary::get_signed(ObjectAddress address) const noexcept {
  const ObjectEntry* entry = find(address);
  return entry != nullptr ? static_cast<std::int32_t>(entry->as_integer()) : 0;
}

void ObjectDictionary::restore_defaults(std::uint16_t first, std::uint16_t last) noexcept {
  for (auto& entry : entries_) {
    if (entry.address.index >= first && entry.address.index <= last) {
      entry.value = entry.default_value;
    }
  }
}

}  // namespace cambio::virtual_rig
