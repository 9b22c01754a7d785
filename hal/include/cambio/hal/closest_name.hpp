#pragma once

// The "did you mean" of every message that refuses a name (a config key, a backend, a behaviour
// or its parameter): one definition, header-only, for every layer that names things.

#include <algorithm>
#include <cstddef>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace cambio::hal {

/// Levenshtein distance: the fewest single-character insertions, deletions and substitutions
/// that turn `a` into `b`.
inline std::size_t edit_distance(std::string_view a, std::string_view b) {
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

/// The first of the `candidates` nearest to `word` by edit_distance, if at most `max_distance`
/// edits away; by default max(2, |word| / 4), a plausible typo. Words and candidates of more
/// than 100 characters are not names: nothing is suggested for or as one.
template <class Names = std::vector<std::string>>
std::optional<std::string> closest_name(std::string_view word, const Names& candidates,
                                        std::optional<std::size_t> max_distance = std::nullopt) {
  // Names are short; a longer word is no typo of one, and the distance costs |word| x |name|.
  constexpr std::size_t kMaxNameChars = 100;
  if (word.size() > kMaxNameChars) return std::nullopt;
  std::optional<std::string> best;
  std::size_t best_distance = max_distance.value_or(std::max<std::size_t>(2, word.size() / 4)) + 1;
  for (const auto& candidate_name : candidates) {
    const std::string_view candidate = candidate_name;
    // The sizes' difference is a lower bound of the distance.
    const std::size_t size_difference = candidate.size() > word.size()
                                            ? candidate.size() - word.size()
                                            : word.size() - candidate.size();
    if (candidate.size() > kMaxNameChars || size_difference >= best_distance) continue;
    const std::size_t distance = edit_distance(word, candidate);
    if (distance < best_distance) {
      best_distance = distance;
      best = std::string(candidate);
    }
  }
  return best;
}

}  // namespace cambio::hal
