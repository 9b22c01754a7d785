// BehaviourRegistry::make(): the program's side of the registry (plugins only add()).
#include <algorithm>

#include "cambio/behaviour/registry.hpp"

namespace cambio::behaviour {
namespace {

// Levenshtein distance, for the "did you mean". control/ may not include the config layer's
// closest_name() (tests/layering_test.cmake), so the registry keeps this small one.
std::size_t edit_distance(std::string_view a, std::string_view b) {
  std::vector<std::size_t> row(b.size() + 1);
  for (std::size_t j = 0; j <= b.size(); ++j) row[j] = j;
  for (std::size_t i = 1; i <= a.size(); ++i) {
    std::size_t diagonal = row[0];
    row[0] = i;
    for (std::size_t j = 1; j <= b.size(); ++j) {
      const std::size_t above = row[j];
      row[j] = std::min({row[j] + 1, row[j - 1] + 1, diagonal + (a[i - 1] == b[j - 1] ? 0 : 1)});
      diagonal = above;
    }
  }
  return row[b.size()];
}

// The nearest of `candidates` to `word`, if closer than a rewrite of half of it; "" otherwise.
template <class Names>
std::string nearest_name(std::string_view word, const Names& candidates) {
  std::string nearest;
  std::size_t nearest_distance = std::string_view::npos;
  for (const auto& candidate : candidates) {
    const std::size_t distance = edit_distance(word, candidate);
    if (distance < nearest_distance && 2 * distance <= std::max(word.size(), candidate.size())) {
      nearest = candidate;
      nearest_distance = distance;
    }
  }
  return nearest;
}

}  // namespace

std::unique_ptr<Behaviour> BehaviourRegistry::make(std::string_view name,
                                                   BehaviourParams& params) const {
  const auto it = factories_.find(name);
  if (it == factories_.end()) {
    std::string message = "no behaviour named '" + std::string(name) + "'";
    const std::vector<std::string> known = names();
    if (const std::string nearest = nearest_name(name, known); !nearest.empty()) {
      message += " (did you mean '" + nearest + "'?)";
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
      if (const std::string nearest = nearest_name(key, absent); !nearest.empty()) {
        message += " (did you mean '" + nearest + "'?)";
      }
    }
    throw std::invalid_argument(message);
  }
  return behaviour;
}

}  // namespace cambio::behaviour
