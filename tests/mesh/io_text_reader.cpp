#include "mesh/io/text_reader.hpp"

#include <doctest/doctest.h>

#include <string>

#include "test_support.hpp"

using softcut::mesh::io::TextReader;
using softcut::test::error_of;

TEST_SUITE("mesh/io/text_reader") {
  TEST_CASE("line mode skips blank and comment lines and counts lines") {
    TextReader r("f.txt", "a b\r\n\n  # only a comment\nc d e # tail\n\nf");
    r.set_comment('#');
    REQUIRE(r.next_line());
    CHECK(r.line() == 1);
    CHECK(r.tokens() == std::vector<std::string_view>{"a", "b"});
    REQUIRE(r.next_line());
    CHECK(r.line() == 4);
    CHECK(r.tokens() == std::vector<std::string_view>{"c", "d", "e"});
    REQUIRE(r.next_line());
    CHECK(r.line() == 6);
    CHECK(r.tokens().size() == 1);
    CHECK(!r.next_line());
  }

  TEST_CASE("token mode crosses lines and resumes after a line-mode read") {
    TextReader r("f.txt", "1 2\n3\nskip me\n4 5");
    CHECK(r.int_token("a") == 1);
    CHECK(r.int_token("b") == 2);
    CHECK(r.int_token("c") == 3);
    CHECK(r.line() == 2);
    REQUIRE(r.next_line());  // "skip me", consumed as a whole
    CHECK(r.int_token("d") == 4);
    r.unget_token();
    CHECK(r.int_token("d") == 4);
    CHECK(r.double_token("e") == 5.0);
    CHECK(error_of([&] { r.token("the answer"); }) == "f.txt:4: unexpected end of file, expected the answer");
  }

  TEST_CASE("raw bytes after a line, and line numbers after them") {
    const std::string text = std::string("HEAD 3\n") + std::string("a\nb") + "\nNEXT\n";
    TextReader r("f.bin", text);
    CHECK(r.token("head") == "HEAD");
    CHECK(r.int_token("n") == 3);
    CHECK(r.take_bytes(3, "data") == "a\nb");
    CHECK(r.token("next") == "NEXT");
    CHECK(r.line() == 4);  // "a\nb" spans lines 2 and 3
    CHECK(error_of([&] { r.take_bytes(100, "more data"); }).find("f.bin:4: file ends inside more data") == 0);
  }

  TEST_CASE("number conversions name the token, the item and the line") {
    TextReader r("f.txt", "\n\n12x 1e400 nan +7 -3 1.5 99999999999");
    CHECK(error_of([&] { r.int_token("node tag"); }) == "f.txt:3: expected an integer for node tag, found '12x'");
    CHECK(error_of([&] { r.to_coord(r.token("x"), "node 4 x"); }).find("f.txt:3: expected a number for node 4 x") == 0);
    CHECK(error_of([&] { r.to_coord(r.token("x"), "node 5 x"); }) ==
          "f.txt:3: node 5 x is not finite (nan); fix or remove that node");
    CHECK(r.int_token("plus") == 7);
    CHECK(error_of([&] { r.to_index(r.token("i"), "node id"); }).find("node id must lie in 0..") != std::string::npos);
    CHECK(error_of([&] { r.int_token("count"); }).find("expected an integer for count, found '1.5'") != std::string::npos);
    CHECK(error_of([&] { r.to_index(r.token("i"), "node id"); }).find("found 99999999999") != std::string::npos);
  }

  TEST_CASE("nothing is left after a last line without a newline") {
    // The cursor then stands one past the end; bytes_left() must not wrap to
    // SIZE_MAX (it bounds reservations announced by headers).
    TextReader r("f.txt", "Vertices 1000000000000");
    REQUIRE(r.next_line());
    CHECK(r.bytes_left() == 0);
    TextReader e("e.txt", "");
    CHECK(e.bytes_left() == 0);
  }

  TEST_CASE("reserve_cap bounds announced counts by the bytes present") {
    using softcut::mesh::io::reserve_cap;
    CHECK(reserve_cap(4000000000LL, 100, 8) == 13);
    CHECK(reserve_cap(5, 100, 8) == 5);
    CHECK(reserve_cap(-1, 100, 8) == 0);
  }
}
