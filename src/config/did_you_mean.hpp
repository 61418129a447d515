// "Did you mean": the closest of the allowed words to a mistyped one, by edit distance.
#pragma once
#include <algorithm>
#include <numeric>
#include <string>
#include <string_view>
#include <vector>

namespace ajx::config {

// The code points of UTF-8 text (a byte that starts no valid sequence counts as one), so that a
// lookalike letter of another alphabet (a Cyrillic о for an o) is one substitution, not two.
inline std::u32string code_points(std::string_view s) {
  std::u32string out;
  for (std::size_t i = 0; i < s.size();) {
    const auto b = static_cast<unsigned char>(s[i]);
    const std::size_t n = b < 0x80 ? 1 : (b >> 5) == 0x6 ? 2 : (b >> 4) == 0xe ? 3 : (b >> 3) == 0x1e ? 4 : 1;
    char32_t c = n == 1 ? b : b & (0x7f >> n);
    std::size_t k = 1;
    for (; k < n && i + k < s.size() && (static_cast<unsigned char>(s[i + k]) >> 6) == 0x2; ++k)
      c = (c << 6) | (static_cast<unsigned char>(s[i + k]) & 0x3f);
    if (k < n) c = b, k = 1;  // cut short: the lead byte alone
    out.push_back(c);
    i += k;
  }
  return out;
}

// Levenshtein distance over code points: insertions, deletions and substitutions, one each.
inline std::size_t edit_distance(std::string_view a_text, std::string_view b_text) {
  const std::u32string a = code_points(a_text), b = code_points(b_text);
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
// its letters changed, and at least one); "" otherwise. Only a suggestion: keys are still
// compared as typed.
template <class Words>
std::string closest(std::string_view word, const Words& allowed) {
  std::string best;
  std::size_t best_d = std::max<std::size_t>(1, code_points(word).size() / 3) + 1;
  for (const auto& w : allowed)
    if (const std::size_t d = edit_distance(word, w); d < best_d) best_d = d, best = std::string(w);
  return best;
}

}  // namespace ajx::config
