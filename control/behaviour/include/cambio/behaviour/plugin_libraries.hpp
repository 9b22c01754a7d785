#pragma once

#include <string>
#include <vector>

#include "cambio/behaviour/registry.hpp"

namespace cambio::behaviour {

/// A plugin that could not be loaded: the file, and why (dlerror's text, the ABI versions, or
/// what its registration threw).
class PluginError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

/// The behaviour plugins a run loaded (shared libraries, see registry.hpp), open until this is
/// destroyed. Whatever a plugin made (the registry's factories, behaviours) holds its code:
/// destroy those first, i.e. declare this object before them. Not thread-safe.
class PluginLibraries {
 public:
  PluginLibraries() = default;
  PluginLibraries(const PluginLibraries&) = delete;
  PluginLibraries& operator=(const PluginLibraries&) = delete;
  /// Closes the libraries, the last loaded first.
  ~PluginLibraries();

  /// Opens `path` (dlopen with RTLD_NOW | RTLD_LOCAL: every symbol resolved now, none shared
  /// with other plugins), checks its ABI version against kBehaviourAbiVersion and lets it
  /// register its behaviours in `registry`. Throws PluginError naming the file; on error the
  /// library is closed again and `registry` keeps only what was there before.
  void load(const std::string& path, BehaviourRegistry& registry);

  /// The paths loaded, in order.
  const std::vector<std::string>& paths() const { return paths_; }

 private:
  std::vector<void*> handles_;
  std::vector<std::string> paths_;
};

}  // namespace cambio::behaviour
