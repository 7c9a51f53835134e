#include "sandbox/patterns.hpp"

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

// State of one sweep of a repetition over the subject (SearchBound::
// repetition): the paths still extending at the next position and the sums.
struct Sweep {
  double acc = 0;      // paths in the run through the last position ('?': those that took its byte)
  double paths = 0;    // paths that reached the item
  double lengths = 0;  // lengths tried past the first, over all paths
  std::size_t runs = 0;  // bytes scanned from the first path in each run
  std::size_t lo = std::string_view::npos, hi = 0;  // positions the new paths reach
};

// x where `keep`, else 0, without a branch: whether a byte is in the class
// can be random along the subject, and a mispredicted branch per byte
// triples a sweep's time. (An infinite count turns to NaN here, but it has
// made the bound infinite already.)
double kept(double x, bool keep) {
  static constexpr double factor[] = {0.0, 1.0};  // a load: compilers make double(keep) a branch
  return x * factor[keep];
}

// One position q of the sweep: `w` paths start the repetition there, `in`
// tells whether q's byte is in the class. Counts are >= 0 (NaN once they
// overflow, which makes the bound infinite anyway).
template <bool maybe, bool plus>
void sweep_step(Sweep& r, double w, bool in, std::size_t q, double* next) {
  double here;
  if (maybe) {
    here = r.acc + w;  // a path from q - 1 that took its byte, or one from q
    r.acc = kept(w, in);
    r.lengths += r.acc;
    r.runs += in & (w > 0);
  } else {
    const double sum = r.acc + w;  // the paths that entered the run so far
    here = plus ? r.acc : sum;
    r.lengths += kept(sum, in);  // each of them takes this byte
    r.runs += in & (sum > 0);    // the bytes scanned from the first path in the run
    r.acc = kept(sum, in);
  }
  r.paths += w;
  next[q] = here;
  const bool reached = here > 0;
  r.lo = reached && r.lo == std::string_view::npos ? q : r.lo;
  r.hi = reached ? q : r.hi;
}

// The sweep over positions [from, to), all with a byte. A function of its
// own: inlined into the bound's, its sums would live in memory, 3x slower.
template <bool maybe, bool plus>
[[gnu::noinline]] Sweep sweep(Sweep r, const double* ways, double* next, const char* s, const bool* member,
                              std::size_t from, std::size_t to) {
  for (std::size_t q = from; q < to; ++q)
    sweep_step<maybe, plus>(r, ways[q], member[static_cast<unsigned char>(s[q])], q, next);
  return r;
}

// Number of search paths the matcher can be on at each subject position,
// item by item, and the steps they cost (an upper bound: every path the
// depth-first matcher can take is counted, whether or not it stops early).
class SearchBound {
 public:
  // Subjects longer than this are counted without positions (memory: 16
  // bytes per subject byte).
  static constexpr std::size_t kMaxPositions = std::size_t(1) << 20;

  // The count's own work is linear in subject and pattern, but both may be
  // megabytes, and a call refused after a second of counting is a call that
  // ran for a second: `limit` caps that work too, each pass charged before
  // it runs. A cell (a subject position in one pass, a byte tested) takes
  // about half a nanosecond, a matcher step about one: at this many steps a
  // cell, a count that gives up at the 1e9-step cap has spent ~0.15 s.
  static constexpr double kCellSteps = 4;
  // An item's fixed cost (parsing, dispatch, a fresh class memo), in cells.
  static constexpr double kItemCells = 32;

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
    if (!scalar_ && hi_ == lo_ && ways_[lo_] == 0) return spend(1);  // every path failed: nothing runs
    if (!spend(kItemCells)) return false;
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

  // Whether the byte at p (< n) is in the class. A set's test walks its
  // text and the passes test many bytes: each item decides each byte value
  // once, and pays for that.
  bool in_class(const Item& it, std::size_t p) {
    const auto c = static_cast<unsigned char>(s_[p]);
    return memo_item_[c] == item_ ? memo_[c] : learn(it, c);
  }

  bool learn(const Item& it, unsigned char c) {
    if (!spend(it.cost)) return false;
    memo_item_[c] = item_;
    memo_[c] = pattern_class_matches(pat_.substr(it.begin, it.end - it.begin), c);
    return memo_[c];
  }

  // Decides the bytes of [from, to) before a pass reads memo_ for them: a
  // pass without calls keeps its sums in registers, twice as fast.
  void learn_bytes(const Item& it, std::size_t from, std::size_t to) {
    for (std::size_t p = from; p < to && !over_; ++p) {
      const auto c = static_cast<unsigned char>(s_[p]);
      if (memo_item_[c] != item_) learn(it, c);
    }
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
    if (!spend(2 * range()) || !grow(hi_ + 1)) return;  // the bytes' classes, then the paths
    const std::size_t end = std::min(hi_ + 1, n_);  // no byte at n
    learn_bytes(it, lo_, end);
    const char* s = s_.data();
    const bool* member = memo_.data();
    const double* ways = ways_.data();
    double* next = next_.data();
    std::size_t lo = n_ + 1, hi = 0;
    double paths = 0;
    for (std::size_t p = lo_; p < end; ++p) {
      const double w = ways[p];
      paths += w;
      const bool keep = (w != 0) & member[static_cast<unsigned char>(s[p])];
      next[p + 1] = keep ? w : 0.0;  // every cell of the new range written: no clearing pass
      lo = keep && lo > n_ ? p + 1 : lo;
      hi = keep ? p + 1 : hi;
    }
    if (hi_ == n_) paths += ways[n_];
    steps_ += paths * it.cost;
    scanned(range());
    settle(lo, hi);
  }

  // A repetition at p tries every length up to the run of class bytes at p
  // (at most one for '?', at least one for '+'), testing each byte of the
  // run once plus the byte that ends it. Each class byte continues every
  // path that entered its run at or before it, so one sweep with a sum that
  // restarts at each non-class byte yields the new paths, the lengths tried
  // and the bytes tested together (no subtraction: exact below 2^53).
  void repetition(const Item& it) {
    if (it.repeat == '?') {
      repetition<true, false>(it);
    } else if (it.repeat == '+') {
      repetition<false, true>(it);
    } else {
      repetition<false, false>(it);
    }
  }

  template <bool maybe, bool plus>
  void repetition(const Item& it) {
    // The bytes' classes, then a sweep that carries three sums.
    if (!spend(3 * range()) || !grow(hi_ + 1)) return;
    const bool any = it.end - it.begin == 1 && pat_[it.begin] == '.';
    const std::size_t bytes_end = std::min(hi_ + 1, n_);
    if (any) {
      memo_.fill(true);
      memo_item_.fill(item_);
    } else {
      learn_bytes(it, lo_, bytes_end);
    }
    Sweep r = sweep<maybe, plus>(Sweep{}, ways_.data(), next_.data(), s_.data(), memo_.data(), lo_, bytes_end);
    if (hi_ == n_) sweep_step<maybe, plus>(r, ways_[n_], false, n_, next_.data());
    // Past hi_ no path starts: the paths in the run through hi_ go on to its
    // end with nothing added, so only that end is sought, byte by byte and
    // charged: a run longer than the limit leaves room for gives up.
    if (r.acc != 0 && hi_ < n_) {
      std::size_t end = hi_ + 1;
      if (!maybe) {
        const double room = std::max(0.0, (limit_ - work_) / kCellSteps / 2);
        const std::size_t stop = room < double(n_ - end) ? end + std::size_t(room) : n_;
        if (any) end = stop;
        while (end < stop && in_class(it, end)) ++end;
        if (end == stop && stop < n_) over_ = true;
      }
      if (!spend(2.0 * double(end - hi_)) || !grow(end)) return;
      std::fill(next_.begin() + std::ptrdiff_t(hi_ + 1), next_.begin() + std::ptrdiff_t(end + 1), r.acc);
      r.lengths += r.acc * double(end - hi_ - 1);  // each takes every byte of the run
      r.runs += end - hi_ - 1;
      r.lo = std::min(r.lo, hi_ + 1);
      r.hi = end;
    }
    steps_ += (2 * r.paths + r.lengths) * it.cost;
    scanned((any ? 0 : double(r.runs)) + 2.0 * double(std::max(r.hi, hi_) - lo_ + 1));
    settle(r.lo == std::string_view::npos ? n_ + 1 : r.lo, r.hi);
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
