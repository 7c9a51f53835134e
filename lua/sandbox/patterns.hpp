#pragma once
// A worst-case work bound for Lua 5.4's string pattern matcher (string.find,
// match, gmatch, gsub), which runs in C where the sandbox's instruction count
// hook never fires: `('a'):rep(40):match(('a*'):rep(40) .. 'b')` backtracks
// for hours. The sandbox (sandbox/policy.cpp) wraps those functions, asks this bound
// before each call and refuses a call whose bound exceeds its budget.
//
// The bound is sound by construction, not a guess: the matcher is a
// depth-first search whose only branch points are the repetition items
// `*` `+` `-` `?`; everything between them (plain classes, captures, `%b`,
// `%f`, back-references `%1`, anchors) runs without choices. The bound walks
// the pattern once, keeping for each subject position the number of search
// paths that can be there: a repetition over class c at position p has at
// most run_c(p) + 1 continuations (run_c(p): class-c bytes from p on), a
// plain class keeps only the paths whose byte matches. After a `%b` or a
// back-reference the position is data, so from there only paths are counted
// (n + 1 lengths per repetition, at most C(n + j, j) length choices after j
// of them). Each path pays its byte tests, scans and comparisons; an
// unanchored search starts one path at every position.
#include <cstddef>
#include <limits>
#include <string_view>

namespace softcut::lua {

enum class PatternCall { find, match, gmatch, gsub };

struct PatternWork {
  double steps = 0;      // upper bound on the matcher's elementary steps (byte tests, scans)
  int repetitions = 0;   // repetition items `*` `+` `-` `?` in the pattern
};

// Bound on the work of one call `string.<call>(subject, pattern, ...)`:
// every start position of an unanchored search (or of gmatch's whole
// iteration, or gsub's), `plain` for string.find's 4th argument, and for gsub
// with a string replacement its length (the replacement is scanned once per
// match). Runs in O(len(pattern) * len(subject)) at most, usually far less
// (an anchored pattern only visits the positions it can reach).
// Gives up (steps: infinity) once the count's own work passes `limit` steps.
PatternWork pattern_work(PatternCall call, std::string_view subject, std::string_view pattern, bool plain = false,
                         std::size_t replacement_length = 0,
                         double limit = std::numeric_limits<double>::infinity());

// Whether byte `c` belongs to the single-character class `cls` (".", "x",
// "%a", "[^%d_-]", ... as Lua patterns spell it). Exposed so that tests can
// compare it with the real matcher byte by byte.
bool pattern_class_matches(std::string_view cls, unsigned char c);

}  // namespace softcut::lua
