#pragma once

#include <any>
#include <vector>

namespace cambio::hal {

/// What the backends of a run offer besides their devices, asked for by type, the way
/// ros2_control's resource manager hands out interfaces: the evaluation asks for the world's
/// ground truth (only a simulator has one), the report for each CAN group's counters, `--out`
/// for a whole-frame renderer. A backend offers an interface by handing out a reference it keeps
/// owning (Backend::offer); whoever asks gets every implementation offered, or none, and never
/// learns which backend it came from. Nobody downcasts a backend to find out what it can do.
///
/// The interface type is the key, exactly: offer<const T>() is found by find<const T>() only.
/// Built while the run is assembled (allocates); read-only afterwards.
class BackendOffers {
 public:
  template <class Interface>
  void offer(Interface& implementation) {
    entries_.emplace_back(&implementation);
  }

  /// Every implementation of `Interface` offered, in the order offered.
  template <class Interface>
  std::vector<Interface*> all() const {
    std::vector<Interface*> found;
    for (const std::any& entry : entries_) {
      if (Interface* const* implementation = std::any_cast<Interface*>(&entry)) {
        found.push_back(*implementation);
      }
    }
    return found;
  }

  /// The first implementation of `Interface` offered, or null when no backend offers one.
  template <class Interface>
  Interface* find() const {
    for (const std::any& entry : entries_) {
      if (Interface* const* implementation = std::any_cast<Interface*>(&entry)) {
        return *implementation;
      }
    }
    return nullptr;
  }

 private:
  std::vector<std::any> entries_;
};

}  // namespace cambio::hal
