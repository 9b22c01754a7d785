#pragma once

// Behaviours by name, and the entry points of a behaviour plugin.
//
// A plugin is a shared library built against the installed package (cambio::behaviour, headers
// only: it links nothing of Câmbio's static libraries). The program dlopen()s it and passes its
// own registry in, so everything a plugin calls here is inline or virtual: BehaviourParams'
// getters and BehaviourRegistry::add(). BehaviourRegistry::make() and
// BehaviourParams::unread_keys() are the program's side.
//
// A plugin's source:
//
//   #include "cambio/behaviour/registry.hpp"
//   class Wander final : public cambio::behaviour::Behaviour { ... };
//   CAMBIO_BEHAVIOUR_PLUGIN(registry) {
//     registry.add("wander", [](cambio::behaviour::BehaviourParams& params) {
//       return std::make_unique<Wander>(params.number("speed_deg_s", 10.0));
//     });
//   }
//
// The factories and behaviours a plugin made hold its code: the program destroys them before it
// closes the library (PluginLibraries).

#include <charconv>
#include <cmath>
#include <cstdint>
#include <functional>
#include <map>
#include <memory>
#include <set>
#include <stdexcept>
#include <string>
#include <string_view>
#include <system_error>
#include <utility>
#include <vector>

#include "cambio/behaviour/behaviour.hpp"

namespace cambio::behaviour {

/// The behaviour API's binary version: a plugin built against another one is refused. Bump it
/// whenever behaviour.hpp or this file changes a type's layout or a virtual function.
inline constexpr std::uint32_t kBehaviourAbiVersion = 1;

/// The experiment file's `behaviour.params`: scalar values by key, as written, each with where
/// it was written ("file:line") for messages. A behaviour reads what it needs with the typed
/// getters; a key it never reads is an error the program reports once the behaviour is made
/// (unread_keys()), as a misspelt key in any config file is.
class BehaviourParams {
 public:
  struct Entry {
    std::string text;   ///< The YAML scalar as written.
    std::string where;  ///< "file:line" of the key, for messages; may be empty.
  };

  BehaviourParams() = default;
  /// `context` names the map in messages (e.g. "behaviour.params").
  explicit BehaviourParams(std::map<std::string, Entry, std::less<>> entries,
                           std::string context = "behaviour.params")
      : entries_(std::move(entries)), context_(std::move(context)) {}

  bool has(std::string_view key) const { return entries_.find(key) != entries_.end(); }

  /// A finite number; `fallback` when the key is absent. Throws std::invalid_argument naming
  /// the key and what it holds when it is not a number.
  double number(std::string_view key, double fallback) {
    const Entry* entry = read(key);
    if (entry == nullptr) return fallback;
    double value = 0.0;
    const char* first = entry->text.data();
    const char* last = first + entry->text.size();
    const auto [end, error] = std::from_chars(first, last, value);
    if (error != std::errc() || end != last || !std::isfinite(value)) {
      fail(key, *entry, "a finite number");
    }
    return value;
  }
  /// An integer; `fallback` when absent. Throws as number().
  std::int64_t integer(std::string_view key, std::int64_t fallback) {
    const Entry* entry = read(key);
    if (entry == nullptr) return fallback;
    std::int64_t value = 0;
    const char* first = entry->text.data();
    const char* last = first + entry->text.size();
    const auto [end, error] = std::from_chars(first, last, value);
    if (error != std::errc() || end != last) fail(key, *entry, "an integer");
    return value;
  }
  /// true/false; `fallback` when absent.
  bool boolean(std::string_view key, bool fallback) {
    const Entry* entry = read(key);
    if (entry == nullptr) return fallback;
    if (entry->text == "true") return true;
    if (entry->text == "false") return false;
    fail(key, *entry, "true or false");
  }
  /// The text as written; `fallback` when absent.
  std::string text(std::string_view key, std::string fallback) {
    const Entry* entry = read(key);
    return entry == nullptr ? fallback : entry->text;
  }

  /// Keys present that no getter asked for, in key order (the program's check).
  std::vector<std::string> unread_keys() const {
    std::vector<std::string> keys;
    for (const auto& [key, entry] : entries_) {
      if (read_.find(key) == read_.end()) keys.push_back(key);
    }
    return keys;
  }
  /// Every key a getter asked for, present or not (the behaviour's parameters).
  const std::set<std::string, std::less<>>& asked_keys() const { return read_; }
  const std::string& context() const { return context_; }
  const std::map<std::string, Entry, std::less<>>& entries() const { return entries_; }

 private:
  const Entry* read(std::string_view key) {
    read_.emplace(key);
    const auto it = entries_.find(key);
    return it == entries_.end() ? nullptr : &it->second;
  }
  [[noreturn]] void fail(std::string_view key, const Entry& entry,
                         std::string_view expected) const {
    std::string message;
    if (!entry.where.empty()) message = entry.where + ": ";
    message += context_ + "." + std::string(key) + ": expected " + std::string(expected) +
               ", found '" + entry.text + "'";
    throw std::invalid_argument(message);
  }

  std::map<std::string, Entry, std::less<>> entries_;
  std::set<std::string, std::less<>> read_;
  std::string context_ = "behaviour.params";
};

/// Makes a behaviour from its parameters; may throw (a bad parameter).
using BehaviourFactory = std::function<std::unique_ptr<Behaviour>(BehaviourParams&)>;

/// Behaviours by name: the program's built-ins and what plugins add.
class BehaviourRegistry {
 public:
  /// Registers `factory` under `name`. Throws std::invalid_argument for an empty name or one
  /// already registered (a plugin may not replace a built-in silently).
  void add(std::string name, BehaviourFactory factory) {
    if (name.empty()) throw std::invalid_argument("a behaviour needs a name");
    if (!factory) throw std::invalid_argument("behaviour '" + name + "' has no factory");
    if (factories_.contains(name)) {
      throw std::invalid_argument("a behaviour named '" + name + "' is already registered");
    }
    factories_.emplace(std::move(name), std::move(factory));
  }
  bool has(std::string_view name) const { return factories_.find(name) != factories_.end(); }
  /// The registered names, sorted.
  std::vector<std::string> names() const {
    std::vector<std::string> out;
    for (const auto& [name, factory] : factories_) out.push_back(name);
    return out;
  }
  /// Makes the behaviour `name` from `params`, then checks that it read every key of `params`.
  /// Throws std::invalid_argument for an unknown name (listing the registered ones, with the
  /// nearest as "did you mean"), for a key it never read, or whatever its factory throws.
  /// The program's side: defined in cambio_behaviour_host, not for plugins.
  std::unique_ptr<Behaviour> make(std::string_view name, BehaviourParams& params) const;

  /// Moves every factory of `other` here (a loaded plugin's, once all its names are free).
  /// Throws as add() for a name taken.
  void merge(BehaviourRegistry&& other) {
    for (auto& [name, factory] : other.factories_) add(name, std::move(factory));
    other.factories_.clear();
  }
  /// Drops every factory (before the libraries whose code they hold are closed).
  void clear() { factories_.clear(); }

 private:
  std::map<std::string, BehaviourFactory, std::less<>> factories_;
};

/// The plugin's entry points, looked up by name with dlsym().
inline constexpr const char* kPluginAbiSymbol = "cambio_behaviour_abi_version";
inline constexpr const char* kPluginRegisterSymbol = "cambio_register_behaviours";
using PluginAbiFunction = std::uint32_t (*)();
using PluginRegisterFunction = void (*)(BehaviourRegistry&);

}  // namespace cambio::behaviour

/// Defines a plugin's two entry points: its ABI version (kBehaviourAbiVersion as it was built)
/// and the function that registers its behaviours; write that function's body after the macro.
/// It may throw (a duplicate name): the program reports the error with the library's path.
#define CAMBIO_BEHAVIOUR_PLUGIN(registry)                                                          \
  extern "C" __attribute__((visibility("default"))) std::uint32_t cambio_behaviour_abi_version() { \
    return ::cambio::behaviour::kBehaviourAbiVersion;                                              \
  }                                                                                                \
  extern "C" __attribute__((visibility("default"))) void cambio_register_behaviours(               \
      ::cambio::behaviour::BehaviourRegistry& registry)
