#pragma once

#include <array>
#include <cstdint>
#include <string>
#include <string_view>

#include "cambio/hal/status.hpp"

namespace cambio::hal {

struct TouchReading {
  std::int64_t stamp_ns = 0;
  bool in_contact = false;
  double normal_force_n = 0.0;  ///< Sum of contact normal forces on the end effector.
  /// Name of the object touched with the largest force, NUL-terminated (fixed size so a reading
  /// can be copied without allocation).
  std::array<char, 64> object_name{};

  std::string_view object() const { return std::string_view(object_name.data()); }
};

/// A touch sensor on an end effector.
class TouchSensor {
 public:
  virtual ~TouchSensor() = default;
  virtual const std::string& name() const = 0;
  /// Newest reading. Real-time safe.
  virtual Status read(TouchReading& out) = 0;
};

}  // namespace cambio::hal
