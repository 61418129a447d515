// "Did you mean": the closest of the allowed words to a mistyped one, by edit distance.
#pragma once
#include <algorithm>
#include <numeric>
#include <string>
#include <string_view>
#include <vector>

namespace ajx::config {

// Levenshtein distance: insertions, deletions and substitutions, one each.
inline std::size_t edit_distance(std::string_view a, std::string_view b) {
  std::vector<std::size_t> row(b.size() + 1);
  std::iota(row.begin(), row.end(), std::size_t{0});
  for (std::size_t i = 1; i <= a.size(); ++i) {
    std::size_t diagonal = row[0];
    row[0] = i;
    for (std::size_t j = 1; j <= b.size(); ++j) {
      const std::size_t above = row[j];
      row[j] = std::min({row[j] + 1, row[j - 1] + 1, diagonal + (a[i - 1] != b[j - 1] ? 1 : 0)});
      diagonal = above;
    }
  }
  return row[b.size()];
}

// The allowed word nearest to `word`, if it is near enough to be a typo (at most a third of
// its letters changed, and at least one); "" otherwise.
template <class Words>
std::string closest(std::string_view word, const Words& allowed) {
  std::string best;
  std::size_t best_d = std::max<std::size_t>(1, word.size() / 3) + 1;
  for (const auto& w : allowed)
    if (const std::size_t d = edit_distance(word, w); d < best_d) best_d = d, best = std::string(w);
  return best;
}

}  // namespace ajx::config
