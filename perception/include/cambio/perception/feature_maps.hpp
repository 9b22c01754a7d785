#pragma once

#include <cstddef>
#include <vector>

#include "cambio/perception/operator_bank.hpp"

namespace cambio::perception {

/// Every feature map of one eye: levels x maps planes of width x height floats, one contiguous
/// buffer sized at construction. Map i of level k is at map(k, i); rows are `width` floats.
class FeatureMaps {
 public:
  FeatureMaps() = default;
  FeatureMaps(int levels, int maps, int width, int height)
      : levels_(levels),
        maps_(maps),
        width_(width),
        height_(height),
        data_(static_cast<std::size_t>(levels) * maps * width * height, 0.0f) {}

  int levels() const { return levels_; }
  int maps() const { return maps_; }
  int width() const { return width_; }
  int height() const { return height_; }
  /// Which maps hold this frame's values (the request they were computed for).
  MapMask computed() const { return computed_; }
  void set_computed(MapMask mask) { computed_ = mask; }

  float* level(int k) { return data_.data() + offset(k, 0); }
  const float* level(int k) const { return data_.data() + offset(k, 0); }
  float* map(int k, int index) { return data_.data() + offset(k, index); }
  const float* map(int k, int index) const { return data_.data() + offset(k, index); }

 private:
  std::size_t offset(int k, int index) const {
    return (static_cast<std::size_t>(k) * maps_ + static_cast<std::size_t>(index)) *
           static_cast<std::size_t>(width_) * static_cast<std::size_t>(height_);
  }
  int levels_ = 0;
  int maps_ = 0;
  int width_ = 0;
  int height_ = 0;
  MapMask computed_ = 0;
  std::vector<float> data_;
};

}  // namespace cambio::perception
