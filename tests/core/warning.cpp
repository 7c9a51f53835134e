#include "core/warning.hpp"

#include <doctest/doctest.h>

using namespace softcut;

TEST_SUITE("core/warning") {
  TEST_CASE("a coded warning ends in [code], and the code reads back") {
    Diagnostics d;
    warn_coded(d, "implausible_size", "mesh: the body is ", 190, " m across");
    REQUIRE(d.warnings.size() == 1);
    CHECK(d.warnings[0] == "mesh: the body is 190 m across [implausible_size]");
    CHECK(warning_code(d.warnings[0]) == "implausible_size");
    CHECK(warning_code(coded_warning("tool_never_touched", "x")) == "tool_never_touched");
  }

  TEST_CASE("text that only looks like a code has none") {
    CHECK(warning_code("plain warning").empty());
    CHECK(warning_code("").empty());
    CHECK(warning_code("range [0, 1]").empty());
    CHECK(warning_code("value [A]").empty());
    CHECK(warning_code("list [1]").empty());
    CHECK(warning_code("no space[x]").empty());
    CHECK(warning_code(" []").empty());
  }
}
