// lua/check.lua: argument checking against lua/api.lua, seen from a scenario.
#include <doctest/doctest.h>

#include "lua_test_support.hpp"

using softcut::test::contains;
using softcut::test::kBoxHead;
using softcut::test::scenario_error;
using softcut::test::write_scenario;

namespace {

// The error of kBoxHead (lines 1-6) followed by `tail` (from line 7 on).
std::string misuse(const std::string& tail) {
  const auto f = write_scenario("check_misuse", std::string(kBoxHead) + tail + "\nreturn s\n", "liver.lua");
  std::string e = scenario_error(f);
  const std::string prefix = f.string() + ":";
  if (e.rfind(prefix, 0) == 0) e = "liver.lua:" + e.substr(prefix.size());
  return e;
}

}  // namespace

TEST_SUITE("lua/check") {
  TEST_CASE("unknown field: suggestion of the closest name, at the caller's line") {
    CHECK(misuse("s:material{ youngs = 3e3, poisson = 0.4 }") ==
          "liver.lua:7: material: unknown field 'youngs' (did you mean 'young'?)");
    CHECK(misuse("s:load{ nodes = tip, forse = {0, 0, -1} }") ==
          "liver.lua:7: load: unknown field 'forse' (did you mean 'force'?)");
    // Far from every name: the valid names are listed instead.
    const std::string e = misuse("s:fix{ zzzzzz = 1 }");
    CHECK(e == "liver.lua:7: fix: unknown field 'zzzzzz' (valid: displacement, name, nodes, path)");
  }

  TEST_CASE("wrong types name the field, the expected type and unit, and what was given") {
    CHECK(misuse("s:material{ young = '3e3', poisson = 0.4 }") ==
          "liver.lua:7: material: field 'young' must be a finite number (Pa), got string '3e3'");
    CHECK(misuse("s:load{ nodes = {1, 2}, normal = 1 }") ==
          "liver.lua:7: load: field 'nodes' must be a node selection (softcut.select.*), got table");
    CHECK(misuse("s:load{ nodes = tip, force = {0, 0} }") ==
          "liver.lua:7: load: field 'force' must be a 3-vector {x, y, z} of finite numbers (N), got table");
    CHECK(misuse("s:material{ 3e3, 0.4 }") == "liver.lua:7: material: expects named fields only (found positional value [1])");
    CHECK(contains(misuse("s:material(3e3)"), "liver.lua:7: material: expects a table of named fields"));
    CHECK(misuse("local r = softcut.ramp.linear{ t1 = 0/0 }")
              .rfind("liver.lua:7: ramp.linear: field 't1' must be a finite number (s), got number ", 0) == 0);
  }

  TEST_CASE("out-of-range values say the bound and why") {
    CHECK(misuse("s:material{ young = 3e3, poisson = 0.5 }") ==
          "liver.lua:7: material: field 'poisson' = 0.5 is out of range: must be < 0.5 (nu -> 0.5 is incompressible, "
          "which linear tets cannot represent)");
    CHECK(misuse("s:material{ young = 0, poisson = 0.3 }") ==
          "liver.lua:7: material: field 'young' = 0 Pa is out of range: must be > 0 Pa (E must be positive)");
    CHECK(misuse("s:material{ young = -5, poisson = 0.3 }").rfind("liver.lua:7: material: field 'young' = -5 Pa", 0) == 0);
    CHECK(misuse("s:probe{ name = 'p', path = {0, 0, 0}, radius = -1, force = 1 }") ==
          "liver.lua:7: probe: field 'radius' = -1 m is out of range: must be > 0 m");
  }

  TEST_CASE("required fields, exclusive groups, enumerations, nested tables") {
    CHECK(misuse("s:fix{}") == "liver.lua:7: fix: missing field 'nodes' (nodes to fix)");
    CHECK(misuse("s:load{ nodes = tip }") == "liver.lua:7: load: give exactly one of force, normal (got none)");
    CHECK(misuse("s:load{ nodes = tip, force = {0, 0, 1}, normal = 1 }") ==
          "liver.lua:7: load: give exactly one of force, normal (got force and normal)");
    CHECK(misuse("s:solver{ backend = 'gpuu' }") ==
          "liver.lua:7: solver: field 'backend': unknown value 'gpuu' (did you mean 'gpu'?)");
    CHECK(misuse("s:operational{ sphere = { centre = {0, 0, 0}, radius = 0.01 } }") ==
          "liver.lua:7: operational: field 'sphere': unknown field 'centre' (did you mean 'center'?)");
    CHECK(misuse("s:material{ tissue = 'livr' }") == "liver.lua:7: material: unknown tissue 'livr' (did you mean 'liver'?)");
  }

  TEST_CASE("ordered fields, declared in api.lua: stop after start (its default included), min not above max") {
    CHECK(misuse("s:probe{ name = 'p', path = {0, 0, 0}, force = 1, start = 2, stop = 1 }") ==
          "liver.lua:7: probe: stop = 1 must be after start = 2");
    CHECK(misuse("s:grasper{ name = 'g', path = {0, 0, 0}, stiffness = 1, stop = 0 }") ==
          "liver.lua:7: grasper: stop = 0 must be after start = 0");
    CHECK(misuse("s:scalpel{ name = 'k', path = {0, 0, 0}, force = 1, cut_pressure = 1e4, start = 1, stop = 1 }") ==
          "liver.lua:7: scalpel: stop = 1 must be after start = 1");
    CHECK(misuse("s:expect{ at = 0, nodes = tip, min = 1, max = 0.5 }") == "liver.lua:7: expect: min = 1 > max = 0.5");
    CHECK(misuse("s:expect{ at = 0, nodes = tip, min = 0.5, max = 0.5 }") == "");
  }

  TEST_CASE("positional arguments are checked too") {
    CHECK(misuse("softcut.select.label('2')") ==
          "liver.lua:7: select.label: field 'label' must be an integer, got string '2'");
    CHECK(misuse("softcut.select.label()") == "liver.lua:7: select.label: missing argument 1 'label' (an integer)");
    CHECK(misuse("local x = tip + 3") ==
          "liver.lua:7: union: field 'other' must be a node selection (softcut.select.*), got number 3");
  }

  TEST_CASE("errors inside helper functions point at the scenario's line, not the library's") {
    const std::string e = misuse("local function add_load(n)\n  s:load{ nodes = n, normal = 'x' }\nend\nadd_load(tip)");
    CHECK(e.rfind("liver.lua:8: load: field 'normal' must be a finite number (N)", 0) == 0);
  }

  TEST_CASE("a misspelled method or library function gets a did-you-mean, as fields do") {
    CHECK(contains(misuse("s:grasp{ name = 'jaw', path = {0, 0, 0}, stiffness = 1 }"),
                   "liver.lua:7: Scenario has no method 'grasp' (did you mean 'grasper'?)"));
    CHECK(contains(misuse("s:fix{ nodes = softcut.select.sphre{ center = {0, 0, 0}, radius = 1 } }"),
                   "liver.lua:7: softcut.select has no function 'sphre' (did you mean 'sphere'?)"));
    CHECK(contains(misuse("local r = softcut.ramp.linaer{ t1 = 1 }"),
                   "liver.lua:7: softcut.ramp has no function 'linaer' (did you mean 'linear'?)"));
    CHECK(contains(misuse("local x = softcut.senario{ duration = 1 }"),
                   "liver.lua:7: softcut has no function 'senario' (did you mean 'scenario'?)"));
    CHECK(contains(misuse("local u = tip:unoin(tip)"), "liver.lua:7: Selection has no method 'unoin' (did you mean 'union'?)"));
    CHECK(contains(misuse("s:on_frame(function(f)\n  local d = f:max_displacment(tip)\nend)"),
                   "liver.lua:8: Frame has no method 'max_displacment' (did you mean 'max_displacement'?)"));
    // Far from every name: the names are listed.
    CHECK(contains(misuse("s:zzzzzzzz()"), "Scenario has no method 'zzzzzzzz' (valid: "));
    // Reading a missing field is still nil (scripts test their own fields),
    // and a user's own method typo is not blamed on softcut.
    CHECK(misuse("s.count = (s.count or 0) + 1\nassert(s.description == nil and softcut.nothing == nil)") == "");
    CHECK(contains(misuse("local t = {}\nlocal x = s.grasp\nt:grasp()"), "attempt to call a nil value (method 'grasp')"));
  }
}
