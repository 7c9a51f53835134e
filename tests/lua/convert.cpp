#include "convert.hpp"

#include <doctest/doctest.h>
#include <lua.hpp>

#include <cstdio>
#include <vector>

#include "lua_test_support.hpp"

namespace {

// Evaluates `expr` in a fresh runtime and converts the result with `fn`.
template <class Fn>
auto convert(const std::string& expr, Fn fn) {
  softcut::lua::Runtime rt;
  rt.run_string("return " + expr, "=t", 1);
  return fn(rt.state(), -1);
}

}  // namespace

TEST_SUITE("lua/convert") {
  TEST_CASE("selections: kinds, shapes and set algebra trees") {
    using K = softcut::sim::NodeSelector::Kind;
    const auto s = convert(
        "softcut.select.sphere{ center = {1, 2, 3}, radius = 0.5 } + softcut.select.label(4) - softcut.select.nodes{ 7 }",
        softcut::lua::to_node_selector);
    CHECK(s.kind == K::difference);
    REQUIRE(s.children.size() == 2);
    CHECK(s.children[0].kind == K::union_of);
    CHECK(s.children[0].children[0].kind == K::sphere);
    CHECK(s.children[0].children[0].center == Eigen::Vector3d(1, 2, 3));
    CHECK(s.children[0].children[0].radius == 0.5);
    CHECK(s.children[0].children[1].label == 4);
    CHECK(s.children[1].ids == std::vector<int>{7});
    CHECK(s.children[1].where == "?");  // no user file (chunk "=t"): unknown line
    const auto b = convert("softcut.select.box{ min = {0, 0, 0}, max = {1, 2, 3} }", softcut::lua::to_node_selector);
    CHECK(b.kind == K::box);
    CHECK(b.max == Eigen::Vector3d(1, 2, 3));
  }

  TEST_CASE("ramps and paths: every field reaches the engine struct") {
    const auto n = convert("2.5", softcut::lua::to_ramp);
    CHECK(n.kind == softcut::tools::Ramp::Kind::constant);
    CHECK(softcut::tools::evaluate(n, 9) == 2.5);
    const auto k = convert("softcut.ramp.keyframes{ times = {0, 1}, values = {3, 4} }", softcut::lua::to_ramp);
    CHECK(k.times == std::vector<double>{0, 1});
    CHECK(k.values == std::vector<double>{3, 4});
    const auto w = convert("softcut.ramp.sine{ amplitude = 2, frequency = 3, phase = 0.5, offset = 1, t0 = 4 }", softcut::lua::to_ramp);
    CHECK((w.amplitude == 2 && w.frequency == 3 && w.phase == 0.5 && w.offset == 1 && w.t0 == 4));
    const auto a = convert("softcut.path.arc{ center = {1, 0, 0}, axis = {0, 1, 0}, start = {2, 0, 0}, sweep = 3, t0 = 1, t1 = 2 }",
                           softcut::lua::to_path);
    CHECK(a.kind == softcut::tools::Path::Kind::arc);
    CHECK(a.axis == Eigen::Vector3d(0, 1, 0));
    CHECK((a.sweep == 3 && a.t0 == 1 && a.t1 == 2));
    const auto p = convert("softcut.path.polyline{ times = {0, 1}, points = {{0, 0, 0}, {1, 1, 1}} }", softcut::lua::to_path);
    REQUIRE(p.points.size() == 2);
    CHECK(p.points[1] == Eigen::Vector3d(1, 1, 1));
  }

  TEST_CASE("malformed tables are errors, not guesses") {
    softcut::lua::Runtime rt;
    lua_State* L = rt.state();
    rt.run_string("return { kind = 'sphere', center = {1, 2} }", "=t", 1);
    CHECK_THROWS_WITH(softcut::lua::to_node_selector(L, -1), doctest::Contains("field 'center'"));
    rt.run_string("return { kind = 'blob' }", "=t", 1);
    CHECK_THROWS_WITH(softcut::lua::to_node_selector(L, -1), doctest::Contains("unknown selection kind 'blob'"));
    rt.run_string("return { kind = 'linear', t1 = 'x' }", "=t", 1);
    CHECK_THROWS_WITH(softcut::lua::to_ramp(L, -1), doctest::Contains("field 't1' must be a number"));
  }

  TEST_CASE("chained set operations come out flat - deep or self-containing selections are errors") {
    using K = softcut::sim::NodeSelector::Kind;
    const auto labels = [](const softcut::sim::NodeSelector& s) {
      std::vector<int> out;
      for (const auto& c : s.children) out.push_back(c.label);
      return out;
    };
    const char* chain = "(function() local s = softcut.select.label(1) for i = 2, 3000 do s = s %s softcut.select.label(i) end "
                        "return s end)()";
    for (const char* op : {"+", "*", "-"}) {
      CAPTURE(op);
      char code[256];
      std::snprintf(code, sizeof code, chain, op);
      const auto s = convert(code, softcut::lua::to_node_selector);
      CHECK(s.kind == (*op == '+' ? K::union_of : *op == '*' ? K::intersection : K::difference));
      REQUIRE(s.children.size() == 3000);
      std::vector<int> expect(3000);
      for (int i = 0; i < 3000; ++i) expect[i] = i + 1;
      CHECK(labels(s) == expect);
      CHECK(softcut::lua::selection_parts(s) == 3001);
    }
    // Only a difference's first member is spliced: a - (b - c) keeps its shape.
    const auto d = convert("softcut.select.label(1) - (softcut.select.label(2) - softcut.select.label(3))",
                           softcut::lua::to_node_selector);
    REQUIRE(d.children.size() == 2);
    CHECK(d.children[1].kind == K::difference);
    CHECK(labels(d.children[1]) == std::vector<int>{2, 3});
    // Different operations nest as written.
    const auto m = convert("(softcut.select.label(1) + softcut.select.label(2)) * softcut.select.label(3) + "
                           "softcut.select.label(4)",
                           softcut::lua::to_node_selector);
    CHECK(m.kind == K::union_of);
    REQUIRE(m.children.size() == 2);
    CHECK(m.children[0].kind == K::intersection);
    CHECK(m.children[0].children[0].kind == K::union_of);
    CHECK(m.children[1].label == 4);

    // An empty operation is not spliced away (evaluating it is an error), and
    // only the first member of a difference is spliced.
    const auto e = convert("(function() local u = softcut.select.label(1) + softcut.select.label(2) "
                           "u.children[2] = { kind = 'union_of', children = {} } return u end)()",
                           softcut::lua::to_node_selector);
    REQUIRE(e.children.size() == 2);
    CHECK(e.children[1].kind == K::union_of);
    CHECK(e.children[1].children.empty());
    const auto f = convert("(function() local d = softcut.select.label(1) - softcut.select.label(2) "
                           "d.children[1] = { kind = 'difference', children = {} } "
                           "d.children[2] = softcut.select.label(3) - softcut.select.label(4) return d end)()",
                           softcut::lua::to_node_selector);
    REQUIRE(f.children.size() == 2);
    CHECK(f.children[0].children.empty());
    CHECK(labels(f.children[1]) == std::vector<int>{3, 4});
    // Lengths are raw: a __len on a member list does not run.
    const auto g = convert("(function() local u = softcut.select.label(1) + softcut.select.label(2) "
                           "setmetatable(u.children, { __len = function() return math.maxinteger end }) return u end)()",
                           softcut::lua::to_node_selector);
    CHECK(labels(g) == std::vector<int>{1, 2});

    using softcut::Error;
    CHECK_THROWS_WITH_AS(convert("(function() local s = softcut.select.label(1) for i = 1, 300 do "
                                 "if i % 2 == 0 then s = s + softcut.select.label(i) else s = s * softcut.select.label(i) end "
                                 "end return s end)()",
                                 softcut::lua::to_node_selector),
                         doctest::Contains("set operations nested more than 200 deep"), Error);
    CHECK_THROWS_WITH_AS(convert("(function() local u = softcut.select.label(1) + softcut.select.label(2) "
                                 "u.children[2] = u return u end)()",
                                 softcut::lua::to_node_selector),
                         doctest::Contains("containing itself"), Error);
    CHECK_THROWS_WITH_AS(convert("(function() local u = softcut.select.label(1) * softcut.select.label(2) "
                                 "u.children[2] = softcut.select.label(3) + u return u end)()",
                                 softcut::lua::to_node_selector),
                         doctest::Contains("contain"), Error);
  }
}
