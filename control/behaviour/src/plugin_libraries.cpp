#include "cambio/behaviour/plugin_libraries.hpp"

#include <dlfcn.h>

namespace cambio::behaviour {
namespace {

std::string dl_error() {
  const char* text = dlerror();
  return text != nullptr ? text : "no reason given";
}

/// Closes a library on every error path of load().
struct OpenLibrary {
  void* handle = nullptr;
  ~OpenLibrary() {
    if (handle != nullptr) dlclose(handle);
  }
};

}  // namespace

PluginLibraries::~PluginLibraries() {
  for (auto it = handles_.rbegin(); it != handles_.rend(); ++it) dlclose(*it);
}

void PluginLibraries::load(const std::string& path, BehaviourRegistry& registry) {
  const std::string where = "behaviour plugin '" + path + "'";
  OpenLibrary library{dlopen(path.c_str(), RTLD_NOW | RTLD_LOCAL)};
  if (library.handle == nullptr) throw PluginError(where + ": cannot be loaded: " + dl_error());

  dlerror();
  const auto abi = reinterpret_cast<PluginAbiFunction>(dlsym(library.handle, kPluginAbiSymbol));
  if (abi == nullptr) {
    throw PluginError(where + ": no " + std::string(kPluginAbiSymbol) +
                      "(): is it a behaviour plugin (CAMBIO_BEHAVIOUR_PLUGIN)? " + dl_error());
  }
  const std::uint32_t version = abi();
  if (version != kBehaviourAbiVersion) {
    throw PluginError(where + ": built for behaviour ABI version " + std::to_string(version) +
                      ", this program has version " + std::to_string(kBehaviourAbiVersion) +
                      ": rebuild it against this installation");
  }
  const auto register_behaviours =
      reinterpret_cast<PluginRegisterFunction>(dlsym(library.handle, kPluginRegisterSymbol));
  if (register_behaviours == nullptr) {
    throw PluginError(where + ": no " + std::string(kPluginRegisterSymbol) + "(): " + dl_error());
  }
  // Registration goes into a scratch registry first: a plugin that throws half-way leaves no
  // factory of its code behind in `registry` once its library is closed.
  BehaviourRegistry added;
  try {
    register_behaviours(added);
  } catch (const std::exception& error) {
    throw PluginError(where + ": registering its behaviours failed: " + error.what());
  } catch (...) {
    // A plugin may throw anything; nothing it throws may end the program.
    throw PluginError(where +
                      ": registering its behaviours failed: it threw something that is "
                      "not a std::exception");
  }
  if (added.names().empty()) throw PluginError(where + ": registered no behaviour");
  for (const std::string& name : added.names()) {
    if (registry.has(name)) {
      throw PluginError(where + ": registers '" + name + "', a name already taken");
    }
  }
  registry.merge(std::move(added));
  handles_.push_back(library.handle);
  library.handle = nullptr;
  paths_.push_back(path);
}

}  // namespace cambio::behaviour
