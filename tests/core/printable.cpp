// engine/core/printable.cpp: text from files is shown without control bytes
// or malformed UTF-8, for every byte value.
#include "core/printable.hpp"

#include <doctest/doctest.h>

#include <string>

TEST_SUITE("core/printable") {
  TEST_CASE("every single byte: printable ASCII stays, everything else becomes \\xNN") {
    for (int c = 0; c < 256; ++c) {
      const std::string in(1, char(c));
      const std::string out = softcut::printable(in);
      CAPTURE(c);
      if (c >= 0x20 && c < 0x7F) {
        CHECK(out == in);
      } else {
        CHECK(out.size() == 4);
        CHECK(out.rfind("\\x", 0) == 0);
      }
      for (char o : out) CHECK((static_cast<unsigned char>(o) >= 0x20 && static_cast<unsigned char>(o) < 0x7F));
    }
  }

  TEST_CASE("well-formed UTF-8 stays - overlong, surrogate and truncated sequences are escaped") {
    CHECK(softcut::printable("Gewebe \xC3\xBC \xE2\x82\xAC \xF0\x9F\x94\xAA") == "Gewebe \xC3\xBC \xE2\x82\xAC \xF0\x9F\x94\xAA");
    CHECK(softcut::printable("\xC0\xAF") == "\\xC0\\xAF");          // overlong '/'
    CHECK(softcut::printable("\xED\xA0\x80") == "\\xED\\xA0\\x80");  // surrogate
    CHECK(softcut::printable("\xE2\x82") == "\\xE2\\x82");          // truncated
    CHECK(softcut::printable("a\x1B[2Jb\0c", 200) == "a\\x1B[2Jb");  // the literal stops at NUL
    CHECK(softcut::printable(std::string("a\0b", 3)) == "a\\x00b");  // a NUL no longer cuts a message short
  }

  TEST_CASE("long text is cut at max_bytes and marked") {
    CHECK(softcut::printable(std::string(300, 'x'), 10) == std::string(10, 'x') + "...");
  }
}
