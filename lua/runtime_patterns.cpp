#include "runtime_patterns.hpp"

#include <algorithm>
#include <array>
#include <cctype>
#include <cmath>
#include <cstdint>
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
  // Subjects longer than this are counted without positions (memory: 24
  // bytes per subject byte).
  static constexpr std::size_t kMaxPositions = std::size_t(1) << 20;

  // The count's own work is linear in subject and pattern, but both may be
  // megabytes, and a call refused after a second of counting is a call that
  // ran for a second: `limit` caps that work too. Each cell it touches (a
  // subject position in one pass, a byte test) is charged this many steps,
  // so a count that gives up at the 1e9-step cap has spent well under a
  // second (a cell costs a fraction of a nanosecond, a matcher step about one).
  static constexpr double kCellSteps = 4;

  SearchBound(std::string_view subject, std::string_view pattern, bool anchored, double limit)
      : s_(subject), pat_(pattern), n_(subject.size()), limit_(limit) {
    if (n_ > kMaxPositions) {
      to_scalar(anchored ? 1 : double(n_) + 1);
      return;
    }
    // The arrays grow with the positions paths reach: an anchored search
    // over a long subject pays for what it can reach, not for the subject.
    if (anchored) {
      if (grow(0)) ways_[0] = 1;
    } else if (spend(double(n_) + 1) && grow(n_)) {
      std::fill(ways_.begin(), ways_.begin() + std::ptrdiff_t(n_ + 1), 1.0);  // every start position
      hi_ = n_;
    }
  }

  // Adds one item; false once this count's own work passes `limit`: no pass
  // starts that would take it past, so it stops within the limit.
  bool add(const Item& it) {
    if (!spend(1)) return false;
    ++item_;  // a fresh class memo
    if (scalar_) {
      scalar_item(it);
    } else if (it.kind == Item::single) {
      it.repeat ? repetition(it) : single(it);
    } else if (it.kind == Item::capture || it.kind == Item::frontier) {
      // Captures keep the position; %f only filters (not applied: an over-count).
      if (!spend(range())) return false;
      steps_ += total() * it.cost;
      scanned(range());
    } else if (it.kind == Item::end_anchor) {
      if (!spend(range())) return false;
      steps_ += total();
      const double at_end = lo_ <= n_ && n_ <= hi_ ? ways_[n_] : 0.0;
      if (at_end == 0) {
        settle_failed();
      } else {
        lo_ = hi_ = n_;
        ways_[n_] = at_end;
      }
    } else {
      // %b and %1 move each path to one position this pass cannot tell
      // without running them: from here on, count paths, not positions.
      if (!spend(range())) return false;
      to_scalar(total());
      scalar_item(it);
    }
    return !over_;
  }

  // Whether the count stayed within its limit (if not, finish() means nothing).
  bool within() const { return !over_; }

  // Total steps, the last return included.
  double finish() const { return steps_ + (scalar_ ? paths_ : total()); }

 private:
  // Charges `cells` of the count's own work; false (and stays false) once
  // that passes the limit, before the work is done.
  bool spend(double cells) {
    work_ += cells * kCellSteps;
    if (work_ > limit_) over_ = true;
    return !over_;
  }

  // Part of the count's work also charged like the matcher's: the call pays
  // for its own analysis.
  void scanned(double cells) { steps_ += cells; }

  double range() const { return double(hi_ - lo_ + 1); }

  double total() const {
    double t = 0;
    for (std::size_t p = lo_; p <= hi_; ++p) t += ways_[p];
    return t;
  }

  // Makes positions up to `last` (and the one past it) addressable, growing
  // geometrically; the new cells are charged.
  bool grow(std::size_t last) {
    const std::size_t need = std::min(last, n_) + 2;
    if (ways_.size() >= need) return true;
    const std::size_t size = std::max(need, std::min(2 * ways_.size(), n_ + 2));
    if (!spend(2.0 * double(size))) return false;
    ways_.resize(size);
    next_.resize(size);
    return true;
  }

  // A set's test walks its text, and a repetition's runs are tested byte by
  // byte: each set is decided once per item and subject byte value.
  bool in_class(const Item& it, std::size_t p) {
    if (p >= n_) return false;
    const auto c = static_cast<unsigned char>(s_[p]);
    const std::string_view cls = pat_.substr(it.begin, it.end - it.begin);
    if (cls[0] != '[') return pattern_class_matches(cls, c);
    if (memo_item_[c] != item_) {
      if (!spend(it.cost)) return false;
      memo_item_[c] = item_;
      memo_[c] = pattern_class_matches(cls, c);
    }
    return memo_[c];
  }

  // End of the run of class bytes from p: the first position past p whose
  // byte is not in the class, or n. Charged byte by byte; a run longer than
  // the limit leaves room for gives up.
  std::size_t run_end(const Item& it, std::size_t p) {
    const double room = std::max(0.0, (limit_ - work_) / kCellSteps);
    const std::size_t stop = room < double(n_ - p) ? p + std::size_t(room) : n_;
    std::size_t q = p;
    while (q < stop && in_class(it, q)) ++q;
    if (q == stop && stop < n_) over_ = true;
    spend(double(q - p + 1));
    scanned(double(q - p + 1));
    return q;
  }

  // Moves the paths in next_[lo..hi] to ways_ (lo > hi: every path failed).
  void settle(std::size_t lo, std::size_t hi) {
    std::swap(ways_, next_);
    if (lo > hi) {
      settle_failed();
      return;
    }
    lo_ = lo;
    hi_ = hi;
  }

  void settle_failed() {
    lo_ = hi_ = 0;
    ways_[0] = 0;
  }

  void single(const Item& it) {
    if (!spend(range()) || !grow(hi_ + 1)) return;
    std::size_t lo = n_ + 1, hi = 0;
    for (std::size_t p = lo_; p <= hi_; ++p) {
      const double w = ways_[p];
      double kept = 0;
      if (w != 0) {
        steps_ += w * it.cost;
        if (in_class(it, p)) {
          kept = w;
          lo = std::min(lo, p + 1);
          hi = p + 1;
        }
      }
      next_[p + 1] = kept;  // every cell of the new range written: no clearing pass
    }
    scanned(range());
    settle(lo, hi);
  }

  // A repetition at p tries every length up to the run of class bytes at p
  // (at most one for '?', at least one for '+'), testing each byte of the
  // run once plus the byte that ends it.
  void repetition(const Item& it) {
    const std::size_t count = hi_ - lo_ + 1;
    if (!spend(3.0 * double(count))) return;  // the lengths, and the sweep's two cursors
    if (last_.size() < count) last_.resize(count);
    const bool any = it.end - it.begin == 1 && pat_[it.begin] == '.';
    const std::size_t plus = it.repeat == '+' ? 1 : 0;
    // Runs share their end: one scan serves every position of a run, so
    // the subject is scanned once per item, however the paths lie on it.
    std::size_t end = 0;
    bool end_known = false;  // [p', end) are class bytes for some p' <= p, `end` is not
    std::size_t lo = n_ + 1, hi = 0, last = lo_;
    for (std::size_t p = lo_; p <= hi_; ++p) {
      if (ways_[p] == 0) {
        last_[p - lo_] = std::max(last, p);  // no path: keeps the ends in order for the sweep
        continue;
      }
      std::size_t longest;
      if (any) {
        longest = it.repeat == '?' ? std::min<std::size_t>(n_ - p, 1) : n_ - p;
      } else if (it.repeat == '?') {
        longest = in_class(it, p) ? 1 : 0;
        scanned(1);
      } else {
        if (!end_known || end < p) {
          end = run_end(it, p);
          end_known = true;
          if (over_) return;
        }
        longest = end - p;
      }
      steps_ += ways_[p] * (double(longest) + 2) * it.cost;
      last = p + longest;
      last_[p - lo_] = last;
      if (p + plus <= last) {
        lo = std::min(lo, p + plus);
        hi = last;
      }
    }
    scanned(2.0 * double(std::max(hi, hi_) - lo_ + 1));
    if (lo > hi) {
      settle(lo, hi);
      return;
    }
    if (!spend(double(hi - lo + 1)) || !grow(hi)) return;
    // next_[q] = sum of ways_[p] over p with p + plus <= q <= last(p). Both
    // ends grow with p (a run's positions share its end), so one sweep adds
    // each p at its first length and drops it past its last. Exact while
    // counts stay below 2^53, so whenever the bound can be within a budget.
    double acc = 0;
    std::size_t add = lo_, drop = lo_;
    const auto paths = [&](std::size_t p) { return p + plus <= last_[p - lo_] ? ways_[p] : 0.0; };
    for (std::size_t q = lo; q <= hi; ++q) {
      for (; add <= hi_ && add + plus <= q; ++add) acc += paths(add);
      for (; drop < add && last_[drop - lo_] < q; ++drop) acc -= paths(drop);
      next_[q] = std::max(acc, 0.0);
    }
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
  double limit_;
  std::vector<double> ways_, next_;   // paths at each reachable subject position; next_: scratch
  std::vector<std::size_t> last_;     // (hi-lo+1) repetition ends, scratch
  std::size_t lo_ = 0, hi_ = 0;       // positions that may hold paths
  bool scalar_ = false;
  double paths_ = 0, scalar_base_ = 0, scalar_choices_ = 1;
  double scalar_repetitions_ = 0;
  double steps_ = 0;
  double work_ = 0;  // of the count itself, in steps
  bool over_ = false;
  std::uint32_t item_ = 0;                          // items added, for the memo
  std::array<std::uint32_t, 256> memo_item_{};      // item whose set test memo_[c] holds
  std::array<bool, 256> memo_{};
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
  SearchBound bound(subject, pattern, anchored, limit);
  for_each_item(pattern, anchored ? 1 : 0, [&](const Item& it) {
    w.repetitions += it.repeat != 0;
    if (bound.within()) bound.add(it);
    return true;  // count all repetitions for the message
  });
  w.steps = bound.within() ? bound.finish() + m : INFINITY;
  if (call == PatternCall::gsub) w.steps += (n + 1) * (double(replacement_length) + 2);  // copies and replacements
  if (std::isnan(w.steps)) w.steps = INFINITY;
  return w;
}

}  // namespace softcut::lua
