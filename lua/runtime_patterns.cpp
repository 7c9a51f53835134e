#include "runtime_patterns.hpp"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <vector>

namespace softcut::lua {

namespace {

// One pattern item as the matcher walks it. A malformed tail ends the list:
// the real matcher raises its error on reaching it, so nothing past it runs.
struct Item {
  enum Kind { single, capture, end_anchor, balance, frontier, back_reference } kind = single;
  std::size_t begin = 0, end = 0;  // class text [begin, end) of a single-character class
  char repeat = 0;                 // '*' '+' '-' '?' or 0
  double cost = 1;                 // steps of one byte test of the class
};

// Byte-class membership with the C library's <cctype> classes, as Lua's
// matcher uses them (same process, same locale).
bool class_letter_matches(unsigned char c, unsigned char letter) {
  bool res;
  switch (std::tolower(letter)) {
    case 'a': res = std::isalpha(c); break;
    case 'c': res = std::iscntrl(c); break;
    case 'd': res = std::isdigit(c); break;
    case 'g': res = std::isgraph(c); break;
    case 'l': res = std::islower(c); break;
    case 'p': res = std::ispunct(c); break;
    case 's': res = std::isspace(c); break;
    case 'u': res = std::isupper(c); break;
    case 'w': res = std::isalnum(c); break;
    case 'x': res = std::isxdigit(c); break;
    case 'z': res = c == 0; break;  // deprecated in Lua 5.2 but still matched
    default: return letter == c;  // an escaped non-letter: that byte itself
  }
  return std::isupper(letter) ? !res : res;
}

// `set` is "[...]" including both brackets.
bool set_matches(std::string_view set, unsigned char c) {
  std::size_t p = 1;
  const std::size_t close = set.size() - 1;
  bool hit = true;
  if (set[p] == '^') {
    hit = false;
    ++p;
  }
  for (; p < close; ++p) {
    const auto at = [&](std::size_t i) { return static_cast<unsigned char>(set[i]); };
    if (set[p] == '%') {
      ++p;
      if (class_letter_matches(c, at(p))) return hit;
    } else if (set[p + 1] == '-' && p + 2 < close) {
      if (at(p) <= c && c <= at(p + 2)) return hit;
      p += 2;
    } else if (at(p) == c) {
      return hit;
    }
  }
  return !hit;
}

// End of the single-character class starting at `p`, or npos when malformed
// (a trailing '%', a '[' without its ']').
std::size_t class_end(std::string_view pat, std::size_t p) {
  const std::size_t m = pat.size();
  const char c = pat[p++];
  if (c == '%') return p < m ? p + 1 : std::string_view::npos;
  if (c != '[') return p;
  if (p < m && pat[p] == '^') ++p;
  do {  // the first byte of a set is a member even when it is ']'
    if (p >= m) return std::string_view::npos;
    if (pat[p++] == '%' && p < m) ++p;
  } while (p >= m || pat[p] != ']');
  return p + 1;
}

// Calls on_item(item) for each item of `pat` from `p` (after any anchor
// '^') until it returns false or the pattern ends or turns malformed.
template <class F>
void for_each_item(std::string_view pat, std::size_t p, F&& on_item) {
  const std::size_t m = pat.size();
  while (p < m) {
    Item it;
    const char c = pat[p];
    const char next = p + 1 < m ? pat[p + 1] : '\0';
    if (c == '(') {
      it.kind = Item::capture;
      p += next == ')' ? 2 : 1;  // position capture "()" or capture start
    } else if (c == ')') {
      it.kind = Item::capture;
      ++p;
    } else if (c == '$' && p + 1 == m) {
      it.kind = Item::end_anchor;
      ++p;
    } else if (c == '%' && next == 'b') {
      if (p + 3 >= m) return;  // "missing arguments to '%b'"
      it.kind = Item::balance;
      p += 4;
    } else if (c == '%' && next == 'f') {
      p += 2;
      if (p >= m || pat[p] != '[') return;
      const std::size_t e = class_end(pat, p);
      if (e == std::string_view::npos) return;
      it.kind = Item::frontier;
      it.cost = 2.0 * double(e - p);  // tests the bytes before and at the position
      p = e;
    } else if (c == '%' && std::isdigit(static_cast<unsigned char>(next))) {
      it.kind = Item::back_reference;
      p += 2;
    } else {
      const std::size_t e = class_end(pat, p);
      if (e == std::string_view::npos) return;
      it.begin = p;
      it.end = e;
      it.cost = double(e - p);  // a set's test walks its text
      p = e;
      if (p < m && (pat[p] == '*' || pat[p] == '+' || pat[p] == '-' || pat[p] == '?')) it.repeat = pat[p++];
    }
    if (!on_item(it)) return;
  }
}

// Number of search paths the matcher can be on at each subject position,
// item by item, and the steps they cost (an upper bound: every path the
// depth-first matcher can take is counted, whether or not it stops early).
class SearchBound {
 public:
  // Subjects longer than this are counted without positions (memory: 16
  // bytes per subject byte).
  static constexpr std::size_t kMaxPositions = std::size_t(1) << 20;

  SearchBound(std::string_view subject, std::string_view pattern, bool anchored)
      : s_(subject), pat_(pattern), n_(subject.size()) {
    const double starts = anchored ? 1 : double(n_) + 1;
    if (n_ > kMaxPositions) {
      to_scalar(starts);
      return;
    }
    ways_.assign(n_ + 2, 0.0);
    next_.assign(n_ + 2, 0.0);
    if (anchored) {
      ways_[0] = 1;
    } else {
      std::fill(ways_.begin(), ways_.begin() + std::ptrdiff_t(n_ + 1), 1.0);  // every start position
      hi_ = n_;
    }
  }

  // Adds one item; false once this count's own work passes `limit` (the
  // count is linear in subject and pattern, but both may be megabytes).
  bool add(const Item& it, double limit) {
    if (scalar_) {
      scalar_item(it);
    } else if (it.kind == Item::single) {
      it.repeat ? repetition(it) : single(it);
    } else if (it.kind == Item::capture || it.kind == Item::frontier) {
      // Captures keep the position; %f only filters (not applied: an over-count).
      steps_ += total() * it.cost;
      scanned(double(hi_ - lo_ + 1));
    } else if (it.kind == Item::end_anchor) {
      steps_ += total();
      const double at_end = lo_ <= n_ && n_ <= hi_ ? ways_[n_] : 0.0;
      std::fill(ways_.begin() + std::ptrdiff_t(lo_), ways_.begin() + std::ptrdiff_t(hi_ + 1), 0.0);
      lo_ = hi_ = n_;
      ways_[n_] = at_end;
    } else {
      // %b and %1 move each path to one position this pass cannot tell
      // without running them: from here on, count paths, not positions.
      to_scalar(total());
      scalar_item(it);
    }
    return work_ <= limit;
  }

  // Total steps, the last return included.
  double finish() const { return steps_ + (scalar_ ? paths_ : total()); }

 private:
  // Work of this count itself, charged like the matcher's.
  void scanned(double cells) {
    steps_ += cells;
    work_ += cells;
  }

  double total() const {
    double t = 0;
    for (std::size_t p = lo_; p <= hi_; ++p) t += ways_[p];
    return t;
  }

  bool in_class(const Item& it, std::size_t p) const {
    return p < n_ &&
           pattern_class_matches(pat_.substr(it.begin, it.end - it.begin), static_cast<unsigned char>(s_[p]));
  }

  // Moves the paths in next_[lo..hi] to ways_ (lo > hi: every path failed).
  void settle(std::size_t lo, std::size_t hi) {
    std::swap(ways_, next_);
    if (lo > hi) {
      lo = hi = 0;
      ways_[0] = 0;
    }
    lo_ = lo;
    hi_ = hi;
  }

  void single(const Item& it) {
    std::fill(next_.begin() + std::ptrdiff_t(lo_), next_.begin() + std::ptrdiff_t(hi_ + 2), 0.0);
    std::size_t lo = n_ + 1, hi = 0;
    for (std::size_t p = lo_; p <= hi_; ++p) {
      if (ways_[p] == 0) continue;
      steps_ += ways_[p] * it.cost;
      if (!in_class(it, p)) continue;
      next_[p + 1] = ways_[p];
      lo = std::min(lo, p + 1);
      hi = p + 1;
    }
    scanned(double(hi_ - lo_ + 1));
    settle(lo, hi);
  }

  // A repetition at p tries every length up to the run of class bytes at p
  // (at most one for '?', at least one for '+'), testing each byte of the
  // run once plus the byte that ends it.
  void repetition(const Item& it) {
    longest_.assign(hi_ - lo_ + 1, 0);
    const bool any = it.end - it.begin == 1 && pat_[it.begin] == '.';
    std::size_t run = 0, hi = 0;
    bool run_known = false;  // `run` is the run at p - 1
    for (std::size_t p = lo_; p <= hi_; ++p) {
      if (ways_[p] == 0) {
        run_known = false;
        continue;
      }
      if (any) {
        run = n_ - p;
      } else if (run_known && run > 0) {
        --run;  // the run at p - 1 less its first byte
      } else {
        run = 0;
        while (in_class(it, p + run)) ++run;
        scanned(double(run));
      }
      run_known = true;
      const std::size_t longest = it.repeat == '?' ? std::min<std::size_t>(run, 1) : run;
      longest_[p - lo_] = longest;
      steps_ += ways_[p] * (double(longest) + 2) * it.cost;
      hi = std::max(hi, p + longest);
    }
    // next_[q] = sum of ways_[p] over p with first(p) <= q <= p + longest(p)
    std::fill(next_.begin() + std::ptrdiff_t(lo_), next_.begin() + std::ptrdiff_t(std::max(hi, hi_) + 2), 0.0);
    std::size_t lo = n_ + 1;
    for (std::size_t p = lo_; p <= hi_; ++p) {
      if (ways_[p] == 0) continue;
      const std::size_t first = it.repeat == '+' ? p + 1 : p;
      const std::size_t last = p + longest_[p - lo_];
      if (first > last) continue;  // '+' without a class byte at p
      next_[first] += ways_[p];
      next_[last + 1] -= ways_[p];
      lo = std::min(lo, first);
    }
    double acc = 0;
    for (std::size_t q = lo_; q <= hi + 1 && q <= n_ + 1; ++q) {
      acc += next_[q];
      next_[q] = q <= hi ? std::max(acc, 0.0) : 0.0;
    }
    scanned(2.0 * double(std::max(hi, hi_) - lo_ + 1));
    settle(lo, hi);
  }

  void to_scalar(double paths) {
    scalar_ = true;
    paths_ = paths;
    scalar_base_ = paths;
    scalar_repetitions_ = 0;
    ways_.clear();
    next_.clear();
    lo_ = hi_ = 0;
  }

  // Past a %b or a back-reference (or on a huge subject): `paths_` paths at
  // unknown positions. A repetition takes one of at most n+1 lengths (2 for
  // '?'), and the lengths along one path sum to at most n: after j
  // repetitions a path that had one way has at most C(n+j, j).
  void scalar_item(const Item& it) {
    const double n = double(n_);
    if (it.kind == Item::balance || it.kind == Item::back_reference) {
      steps_ += paths_ * (n + 1);  // one scan or comparison of up to n bytes
    } else if (it.kind == Item::single && it.repeat) {
      const double children = it.repeat == '?' ? 2 : n + 1;
      steps_ += paths_ * (children + 1) * it.cost;
      ++scalar_repetitions_;
      scalar_choices_ *= (n + scalar_repetitions_) / scalar_repetitions_;
      paths_ = std::min(paths_ * children, scalar_base_ * scalar_choices_);
    } else {
      steps_ += paths_ * it.cost;
    }
  }

  std::string_view s_, pat_;
  std::size_t n_;
  std::vector<double> ways_, next_;  // (n+2) paths at each subject position; next_: scratch
  std::vector<std::size_t> longest_;  // (hi-lo+1) repetition lengths, scratch
  std::size_t lo_ = 0, hi_ = 0;       // positions that may hold paths
  bool scalar_ = false;
  double paths_ = 0, scalar_base_ = 0, scalar_choices_ = 1;
  double scalar_repetitions_ = 0;
  double steps_ = 0;
  double work_ = 0;  // of the count itself (part of steps_)
};

}  // namespace

bool pattern_class_matches(std::string_view cls, unsigned char c) {
  if (cls.empty()) return false;
  switch (cls[0]) {
    case '.': return true;
    case '%': return cls.size() > 1 && class_letter_matches(c, static_cast<unsigned char>(cls[1]));
    case '[': return cls.size() > 2 && set_matches(cls, c);
    default: return static_cast<unsigned char>(cls[0]) == c;
  }
}

PatternWork pattern_work(PatternCall call, std::string_view subject, std::string_view pattern, bool plain,
                         std::size_t replacement_length, double limit) {
  PatternWork w;
  const double n = double(subject.size());
  const double m = double(pattern.size());
  // string.find without specials is a memchr + memcmp search at each start.
  if (call == PatternCall::find && (plain || pattern.find_first_of("^$*+?.([%-") == std::string_view::npos)) {
    w.steps = (n + 1) * (m + 1);
    return w;
  }
  // gmatch has no anchor: its '^' is an ordinary byte.
  const bool anchored = call != PatternCall::gmatch && !pattern.empty() && pattern[0] == '^';
  SearchBound bound(subject, pattern, anchored);
  bool within = true;
  for_each_item(pattern, anchored ? 1 : 0, [&](const Item& it) {
    w.repetitions += it.repeat != 0;
    within = within && bound.add(it, limit);
    return true;  // count all repetitions for the message
  });
  w.steps = within ? bound.finish() + m : INFINITY;
  if (call == PatternCall::gsub) w.steps += (n + 1) * (double(replacement_length) + 2);  // copies and replacements
  if (std::isnan(w.steps)) w.steps = INFINITY;
  return w;
}

}  // namespace softcut::lua
