// Nearest-key search by optimal-string-alignment distance (Damerau-Levenshtein restricted to
// non-overlapping swaps), case-insensitive.
#include "scenarios/key_suggestion.hpp"

#include <algorithm>
#include <cctype>

namespace acdr {

namespace {

constexpr std::size_t kMaxCompared = 256;

char lower(char c) { return static_cast<char>(std::tolower(static_cast<unsigned char>(c))); }

}  // namespace

int edit_distance(std::string_view a, std::string_view b) {
  a = a.substr(0, std::min(a.size(), kMaxCompared));
  b = b.substr(0, std::min(b.size(), kMaxCompared));
  const std::size_t n = a.size(), m = b.size();
  // Three rolling rows: i-2, i-1, i.
  std::vector<int> prev2(m + 1), prev(m + 1), cur(m + 1);
  for (std::size_t j = 0; j <= m; ++j) prev[j] = static_cast<int>(j);
  for (std::size_t i = 1; i <= n; ++i) {
    cur[0] = static_cast<int>(i);
    for (std::size_t j = 1; j <= m; ++j) {
      const int cost = lower(a[i - 1]) == lower(b[j - 1]) ? 0 : 1;
      int d = std::min({prev[j] + 1, cur[j - 1] + 1, prev[j - 1] + cost});
      if (i > 1 && j > 1 && lower(a[i - 1]) == lower(b[j - 2]) &&
          lower(a[i - 2]) == lower(b[j - 1])) {
        d = std::min(d, prev2[j - 2] + 1);
      }
      cur[j] = d;
    }
    std::swap(prev2, prev);
    std::swap(prev, cur);
  }
  return prev[m];
}

std::optional<std::string> nearest_key(std::string_view typed,
                                       const std::vector<std::string>& known) {
  if (typed.empty() || known.empty()) return std::nullopt;
  // A key typed without its unit ("spacing" for "spacing_mm") is the commonest slip.
  for (const std::string& k : known) {
    if (k.size() > typed.size() + 1 && k[typed.size()] == '_' &&
        edit_distance(std::string_view(k).substr(0, typed.size()), typed) == 0) {
      return k;
    }
  }
  int best = 1 << 30;
  const std::string* best_key = nullptr;
  for (const std::string& k : known) {
    const int d = edit_distance(typed, k);
    if (d < best) {
      best = d;
      best_key = &k;
    }
  }
  // Plausible typo: a third of the length, at least 2 edits, at most 4.
  const int limit = std::clamp(static_cast<int>(typed.size()) / 3, 2, 4);
  if (best_key == nullptr || best > limit || best >= static_cast<int>(best_key->size())) {
    return std::nullopt;
  }
  return *best_key;
}

}  // namespace acdr
