#include "mesh/io/base64.hpp"

#include <doctest/doctest.h>

#include <random>

using softcut::mesh::io::base64_decode;
using softcut::mesh::io::base64_encode;

TEST_SUITE("mesh/io/base64") {
  TEST_CASE("RFC 4648 test vectors") {
    const char* plain[] = {"", "f", "fo", "foo", "foob", "fooba", "foobar"};
    const char* coded[] = {"", "Zg==", "Zm8=", "Zm9v", "Zm9vYg==", "Zm9vYmE=", "Zm9vYmFy"};
    for (int i = 0; i < 7; ++i) {
      CHECK(base64_encode(plain[i]) == coded[i]);
      CHECK(base64_decode(coded[i]).value() == plain[i]);
    }
  }

  TEST_CASE("concatenated padded streams and whitespace decode to the concatenation") {
    CHECK(base64_decode("Zg==Zm8=\n  Zm9v").value() == "ffofoo");
  }

  TEST_CASE("bad input is refused with its offset") {
    std::size_t at = 0;
    CHECK(!base64_decode("Zm9v!A==", &at));
    CHECK(at == 4);
    CHECK(!base64_decode("Zm9", &at));  // truncated group
    CHECK(!base64_decode("Z===", &at));  // too much padding
    CHECK(!base64_decode("Zg=a", &at));  // data after padding
  }

  TEST_CASE("random bytes round-trip") {
    std::mt19937 rng(7);
    for (int len = 0; len < 200; ++len) {
      std::string s(std::size_t(len), '\0');
      for (auto& c : s) c = char(rng() & 255);
      const std::string e = base64_encode(s);
      CHECK(e.size() == std::size_t((len + 2) / 3 * 4));
      CHECK(base64_decode(e).value() == s);
    }
  }
}
