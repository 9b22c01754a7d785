// BehaviourRegistry::make(): the program's side of the registry (plugins only add()).
#include <algorithm>

#include "cambio/behaviour/registry.hpp"
#include "cambio/hal/closest_name.hpp"

namespace cambio::behaviour {

std::unique_ptr<Behaviour> BehaviourRegistry::make(std::string_view name,
                                                   BehaviourParams& params) const {
  const auto it = factories_.find(name);
  if (it == factories_.end()) {
    std::string message = "no behaviour named '" + std::string(name) + "'";
    const std::vector<std::string> known = names();
    if (const auto nearest = hal::closest_name(name, known)) {
      message += " (did you mean '" + *nearest + "'?)";
    }
    std::string list;
    for (const std::string& entry : known) list += (list.empty() ? "" : ", ") + entry;
    message += "; registered: " + (list.empty() ? std::string("none") : list);
    throw std::invalid_argument(message);
  }
  std::unique_ptr<Behaviour> behaviour;
  try {
    behaviour = it->second(params);
  } catch (const std::exception&) {
    throw;
  } catch (...) {
    // A plugin's factory may throw anything; nothing it throws may end the program.
    throw std::invalid_argument("behaviour '" + std::string(name) +
                                "': its factory threw something that is not a std::exception");
  }
  if (!behaviour) {
    throw std::invalid_argument("behaviour '" + std::string(name) + "': its factory made nothing");
  }
  const std::vector<std::string> unread = params.unread_keys();
  if (!unread.empty()) {
    std::string message;
    for (const std::string& key : unread) {
      const std::string& where = params.entries().at(key).where;
      if (!message.empty()) message += "\n";
      message += (where.empty() ? "" : where + ": ") + params.context() + "." + key +
                 ": behaviour '" + std::string(name) + "' has no parameter of that name";
      std::vector<std::string> absent;  // What it asked for that the file does not give.
      for (const std::string& asked : params.asked_keys()) {
        if (!params.has(asked)) absent.push_back(asked);
      }
      if (const auto nearest = hal::closest_name(key, absent)) {
        message += " (did you mean '" + *nearest + "'?)";
      }
    }
    throw std::invalid_argument(message);
  }
  return behaviour;
}

}  // namespace cambio::behaviour
