#include "sandbox/patterns.hpp"

#include <doctest/doctest.h>
#include <lua.hpp>

#include <cmath>
#include <random>
#include <string>
#include <vector>

#include "lua/lua_test_support.hpp"

using softcut::lua::pattern_class_matches;
using softcut::lua::pattern_work;
using softcut::lua::PatternCall;
using softcut::test::contains;

namespace {

double choose(double n, double k) {
  double c = 1;
  for (double i = 1; i <= k; ++i) c = c * (n - k + i) / i;
  return c;
}

std::string rep(const std::string& s, int n) {
  std::string r;
  for (int i = 0; i < n; ++i) r += s;
  return r;
}

}  // namespace

TEST_SUITE("lua/sandbox/patterns") {
  TEST_CASE("class membership agrees with Lua's own matcher for every byte") {
    // The bound is only sound if its runs of class bytes are never shorter
    // than the matcher's: compare with string.find(char, '^' .. class .. '()').
    lua_State* L = luaL_newstate();
    luaL_openlibs(L);
    REQUIRE(luaL_dostring(L, "return function(cls) return (pcall(string.find, 'x', cls)) end") == LUA_OK);
    REQUIRE(luaL_dostring(L, "return function(cls) local t = {} for c = 0, 255 do "
                             "t[c + 1] = string.find(string.char(c), '^' .. cls .. '()') ~= nil end "
                             "return t end") == LUA_OK);
    std::vector<std::string> classes = {".", "a", "%a", "%A", "%c", "%d", "%D", "%g", "%l", "%p", "%s", "%S", "%u",
                                        "%w", "%W", "%x", "%X", "%z", "%Z", "%%", "%.", "%]", "%z", "[abc]", "[^abc]", "[a-z]",
                                        "[]]", "[^]]", "[]-a]", "[a-]", "[-a]", "[%a_]", "[^%s,]", "[%]]", "[%-]",
                                        "[a-c-e]", "[%w-z]", "[z-a]", "[^]]", "[^^]", "[\x80-\xff]", "[%d%.eE+-]"};
    std::mt19937 rng(7);
    const std::string alphabet = "ab]^-%z0.s[";
    while (classes.size() < 600) {  // random sets from an alphabet rich in the set syntax's own bytes
      std::string set = "[";
      const int len = 1 + int(rng() % 7);
      for (int i = 0; i < len; ++i) {
        const char c = alphabet[rng() % alphabet.size()];
        if (c == '%') set += std::string("%") + alphabet[rng() % alphabet.size()];  // an escape
        else if (c != ']' || set == "[" || set == "[^") set += c;  // ']' only first: it would end the set
      }
      set += ']';
      lua_pushvalue(L, -2);  // keep only sets Lua accepts
      lua_pushlstring(L, set.data(), set.size());
      lua_call(L, 1, 1);
      if (lua_toboolean(L, -1)) classes.push_back(set);
      lua_pop(L, 1);
    }
    int mismatches = 0;
    for (const std::string& cls : classes) {
      lua_pushvalue(L, -1);
      lua_pushlstring(L, cls.data(), cls.size());
      REQUIRE(lua_pcall(L, 1, 1, 0) == LUA_OK);
      for (int c = 0; c < 256; ++c) {
        lua_rawgeti(L, -1, c + 1);
        const bool lua_says = lua_toboolean(L, -1);
        lua_pop(L, 1);
        if (lua_says != pattern_class_matches(cls, static_cast<unsigned char>(c))) {
          ++mismatches;
          INFO("class " << cls << " byte " << c);
          CHECK(lua_says == pattern_class_matches(cls, static_cast<unsigned char>(c)));
        }
      }
      lua_pop(L, 1);
    }
    CHECK(mismatches == 0);
    CHECK(classes.size() == 600);
    lua_close(L);
  }

  TEST_CASE("the catastrophic pattern's bound covers every path the matcher walks") {
    // ('a*')^k .. 'b' over a^n fails everywhere: the matcher visits every
    // choice of k lengths summing to <= n, C(n + k, k) leaves (closed form).
    for (int n : {0, 1, 5, 12}) {
      for (int k : {1, 2, 3, 6}) {
        const std::string subject(std::size_t(n), 'a');
        const std::string pat = "^" + rep("a*", k) + "b";
        const double steps = pattern_work(PatternCall::match, subject, pat).steps;
        const double leaves = choose(n + k, k);
        INFO("n " << n << " k " << k);
        CHECK(steps >= leaves);
        CHECK(steps <= 30.0 * (k + 2) * leaves + 10 * n + 10);  // and not absurdly loose
        // Unanchored: the same from every start position.
        const double all = pattern_work(PatternCall::find, subject, pat.substr(1)).steps;
        double sum = 0;
        for (int s = 0; s <= n; ++s) sum += choose(n - s + k, k);
        CHECK(all >= sum);
        CHECK(all <= 30.0 * (k + 2) * sum + 10 * n + 10);
      }
    }
    const double hours = pattern_work(PatternCall::match, std::string(40, 'a'), rep("a*", 40) + "b").steps;
    CHECK(hours >= choose(80, 40));  // ~1e23
  }

  TEST_CASE("captures, back-references, %b and %f cannot hide the branching") {
    const std::string a40(40, 'a');
    for (const std::string& pat :
         {rep("(a*)", 20) + "b", "(a*)" + rep("a*%1", 15) + "b", rep("a*%f[a]", 20) + "b", rep(".-%b()", 15) + "z",
          "(a*)%1" + rep("a*", 20) + "b", rep("a?", 40) + rep("a", 40) + "b"}) {
      INFO(pat);
      CHECK(pattern_work(PatternCall::match, a40 + "(a)(a)(a)", pat).steps > 1e12);
      CHECK(pattern_work(PatternCall::gmatch, a40, pat).steps > 1e12);
      CHECK(pattern_work(PatternCall::gsub, a40, pat).steps > 1e12);
    }
    // A %b's end and a back-reference's length are data: a repetition after
    // one may start anywhere.
    CHECK(pattern_work(PatternCall::match, "(" + std::string(30, 'a') + ")", "^%b()" + rep("a*", 10) + "b").steps >=
          1.0);
  }

  TEST_CASE("ordinary patterns over short subjects get small bounds") {
    const struct {
      PatternCall call;
      std::string subject, pattern;
      bool plain = false;
    } uses[] = {
        {PatternCall::gsub, "Hello ${name}, frame ${n} of ${n}.", "%${(%w+)}"},
        {PatternCall::gmatch, "node,12,0.25,-3e-4,,tip", "([^,]*)"},
        {PatternCall::match, "f(a, g(b, c), d) + 1", "%b()"},
        {PatternCall::match, "  stiffness = 3.5e3  # Pa", "^%s*([%w_]+)%s*=%s*(.-)%s*#"},
        {PatternCall::match, "say \"hi\" and \"bye\"", "([\"'])(.-)%1"},
        {PatternCall::gsub, "the cut, the tool", "%f[%w]the%f[%W]"},
        {PatternCall::match, std::string(200, 'x') + " = " + std::string(200, 'y'), "^(%w+)%s*=%s*(.*)$"},
        {PatternCall::match, "liver_left-lobe.v2", "^[%w_%-%.]+$"},
        {PatternCall::gsub, "softcut.select.box", "^softcut%."},
        {PatternCall::find, "a.b*c(d", "*c(", true},
    };
    for (const auto& u : uses) {
      INFO(u.pattern);
      CHECK(pattern_work(u.call, u.subject, u.pattern, u.plain).steps < 2e5);
    }
    // Work grows linearly with the subject for a fixed simple pattern.
    std::string csv;
    for (int i = 0; i < 2000; ++i) csv += std::to_string(i) + "," + std::to_string(i * 0.5) + ",-" + std::to_string(i) + "\n";
    const double one = pattern_work(PatternCall::gmatch, csv, "(%d+),([^,]+),([^\n]+)").steps;
    CHECK(one < 200.0 * double(csv.size()));
    CHECK(pattern_work(PatternCall::gsub, csv, "%s+", 1).steps < 50.0 * double(csv.size()));
  }

  TEST_CASE("an anchored search costs what it can reach, whatever the subject length") {
    const std::string big = "word" + std::string(500000, ' ');
    CHECK(pattern_work(PatternCall::match, big, "^[%w_]+").steps < 100);
    CHECK(pattern_work(PatternCall::find, big, "^%a%w*").steps < 100);
    // gmatch has no anchor: '^' is an ordinary byte there, every start counts.
    CHECK(pattern_work(PatternCall::gmatch, big, "^[%w_]+").steps > double(big.size()));
  }

  TEST_CASE("the count's own work is linear in the subject and stays within the limit") {
    // A review found one refusal taking 12 s: a run of class bytes was
    // rescanned from every path that entered it (quadratic with paths on
    // every other byte, as 'a' leaves them on ("ab"):rep(n)), and each byte
    // test walked a set's whole text uncounted. Now a run is scanned once per
    // item and a set decided once per byte value, both charged against the
    // limit: a limit linear in the subject gives the bound.
    const int half = 16384;
    const std::string ab = rep("ab", half);
    const double n = double(ab.size());
    for (PatternCall call : {PatternCall::find, PatternCall::gmatch, PatternCall::gsub}) {
      for (const char* pat : {"a[ab]*c", "a[ab]-c", "a[ab]+c", "a%w*c"}) {
        INFO(pat);
        // The matcher tries every length of the run after each 'a': at least
        // half * half lengths in all, none of them followed by a 'c'.
        const double steps = pattern_work(call, ab, pat, false, 0, 1000 * n).steps;
        CHECK(std::isfinite(steps));
        CHECK(steps >= double(half) * half);
        CHECK(steps <= 20 * n * n);
      }
      for (const char* pat : {"a[ab]?c", "a%w?c"}) {  // a '?' takes one byte at most: linear
        INFO(pat);
        CHECK(pattern_work(call, ab, pat, false, 0, 1000 * n).steps < 100 * n);
      }
    }
    // A 1 MiB set: the matcher walks its text at each of 4096 bytes, the
    // count once per byte value, and that once is charged.
    const std::string a(4096, 'a');
    const std::string set = "[" + std::string(std::size_t(1) << 20, 'b') + "]";
    for (const std::string& pat : {set, set + "*", "^" + set + "?"}) {
      const double steps = pattern_work(PatternCall::find, a, pat, false, 0, 1e8).steps;
      CHECK(std::isfinite(steps));
      CHECK(steps >= (pat[0] == '^' ? 1.0 : 4096.0) * double(set.size()));
      CHECK(std::isinf(pattern_work(PatternCall::find, a, pat, false, 0, 1e6).steps));
    }
    // An anchored search allocates and visits only the positions it reaches.
    const std::string spaced = "word" + std::string(std::size_t(1) << 19, ' ');
    CHECK(std::isfinite(pattern_work(PatternCall::match, spaced, "^[%w_]+", false, 0, 1e3).steps));
  }

  TEST_CASE("a limit only ever turns the bound infinite") {
    // Giving up is the limit's only effect: a count that fits in it gives
    // the bound it gives without one, and a larger limit never gives up
    // where a smaller one did not.
    std::mt19937 rng(11);
    const std::vector<std::string> items = {"a", "b", "%a", ".", "[ab]", "[^a]",
                                            " ", "(a*)", "()", "%b()", "%f[a]", "%1"};
    const char* const repeats[] = {"", "*", "+", "-", "?"};
    const std::string alphabet = "aab( )";
    for (int i = 0; i < 300; ++i) {
      std::string subject;
      const int length = int(rng() % 300);
      while (int(subject.size()) < length) subject += std::string(1 + rng() % 8, alphabet[rng() % alphabet.size()]);
      std::string pat = rng() % 3 ? "" : "^";
      for (int k = 1 + int(rng() % 6); k > 0; --k) {
        const std::string& item = items[rng() % items.size()];
        pat += item;
        if (item.size() == 1 || item == "%a" || item[0] == '[')
          pat += repeats[rng() % 5];
      }
      const PatternCall call = PatternCall(rng() % 4);
      const double unlimited = pattern_work(call, subject, pat).steps;
      bool fitted = false;
      for (double limit = 1; limit < 1e8; limit *= 4) {
        const double steps = pattern_work(call, subject, pat, false, 0, limit).steps;
        INFO("subject '" << subject << "' pattern '" << pat << "' limit " << limit);
        CHECK((std::isinf(steps) || steps == unlimited));
        CHECK((!fitted || steps == unlimited));
        fitted = fitted || std::isfinite(steps);
      }
      CHECK((fitted || std::isinf(unlimited)));
    }
  }

  TEST_CASE("malformed patterns get a bound and Lua's own error in the sandbox") {
    for (const char* pat : {"[a", "%", "a*%b(", "%f", "%fa", "(a*", "a*)", "%9", "[%", "[^"}) {
      INFO(pat);
      CHECK(std::isfinite(pattern_work(PatternCall::match, "aaaa(", pat).steps));
    }
    const std::string e = softcut::test::lua_error("return ('abc'):match('a[b')");
    CHECK(contains(e, "malformed pattern"));
    CHECK(softcut::test::lua_error("return ('abc'):find('x[b')") == "");  // lazy, as Lua: never reached
  }
}
