#include "core/suggest.hpp"

#include <doctest/doctest.h>

using softcut::suggest;

TEST_SUITE("core/suggest") {
  TEST_CASE("a near miss is named, a far one lists the valid names sorted") {
    CHECK(suggest("corotationl", {"linear", "corotational", "neohookean"}) == " (did you mean 'corotational'?)");
    CHECK(suggest("NeoHookean", {"linear", "corotational", "neohookean"}) == " (did you mean 'neohookean'?)");
    CHECK(suggest("lin", {"linear", "corotational"}) == " (did you mean 'linear'?)");      // a prefix
    CHECK(suggest("lienar", {"linear", "corotational"}) == " (did you mean 'linear'?)");   // a transposition
    CHECK(suggest("elastic", {"linear", "corotational"}) == " (valid: corotational, linear)");
  }
}
