#include "core/suggest.hpp"

#include <algorithm>
#include <cctype>
#include <cstdlib>
#include <vector>

namespace softcut {

namespace {

std::string lower(std::string_view s) {
  std::string out(s);
  for (char& c : out) c = char(std::tolower(static_cast<unsigned char>(c)));
  return out;
}

// Optimal string alignment distance (edits and adjacent transpositions);
// 99 when the lengths differ by more than 3.
int distance(const std::string& a, const std::string& b) {
  const int la = int(a.size()), lb = int(b.size());
  if (std::abs(la - lb) > 3) return 99;
  std::vector<int> prevprev(size_t(lb) + 1), prev(size_t(lb) + 1), cur(size_t(lb) + 1);
  for (int j = 0; j <= lb; ++j) prev[size_t(j)] = j;
  for (int i = 1; i <= la; ++i) {
    cur[0] = i;
    for (int j = 1; j <= lb; ++j) {
      const int cost = a[size_t(i - 1)] == b[size_t(j - 1)] ? 0 : 1;
      int d = std::min({prev[size_t(j)] + 1, cur[size_t(j - 1)] + 1, prev[size_t(j - 1)] + cost});
      if (i > 1 && j > 1 && a[size_t(i - 1)] == b[size_t(j - 2)] && a[size_t(i - 2)] == b[size_t(j - 1)])
        d = std::min(d, prevprev[size_t(j - 2)] + 1);
      cur[size_t(j)] = d;
    }
    prevprev.swap(prev);
    prev.swap(cur);
  }
  return prev[size_t(lb)];
}

}  // namespace

std::string suggest(std::string_view word, std::initializer_list<std::string_view> names) {
  std::vector<std::string_view> sorted(names);
  std::sort(sorted.begin(), sorted.end());
  const std::string w = lower(word);
  std::string_view best;
  int bestd = 1 << 30;
  for (std::string_view n : sorted) {
    const std::string l = lower(n);
    int d = distance(w, l);
    if (l.compare(0, w.size(), w) == 0 || w.compare(0, l.size(), l) == 0) d = std::min(d, 1);
    if (d < bestd) best = n, bestd = d;
  }
  if (!best.empty() && bestd <= std::max(1, int(word.size()) / 3)) return " (did you mean '" + std::string(best) + "'?)";
  std::string out = " (valid: ";
  for (size_t k = 0; k < sorted.size(); ++k) out += (k ? ", " : "") + std::string(sorted[k]);
  return out + ")";
}

}  // namespace softcut
