// engine/core/json_text.cpp: every string becomes valid JSON that reads back
// (well-formed UTF-8 unchanged; other bytes as U+FFFD), whatever its bytes.
#include "core/json_text.hpp"

#include <doctest/doctest.h>

#include <nlohmann/json.hpp>
#include <random>
#include <string>

TEST_SUITE("core/json_text") {
  TEST_CASE("every byte value alone and all 256 together give valid JSON") {
    std::string all;
    for (int c = 0; c < 256; ++c) {
      const std::string in(1, char(c));
      all += in;
      const std::string text = softcut::json_string(in);
      CAPTURE(c);
      const nlohmann::json j = nlohmann::json::parse(text);  // throws on invalid JSON
      REQUIRE(j.is_string());
      if (c < 0x80) CHECK(j.get<std::string>() == in);
      else CHECK(j.get<std::string>() == "\xEF\xBF\xBD");  // a lone byte >= 0x80 is not UTF-8
    }
    CHECK_NOTHROW((void)nlohmann::json::parse(softcut::json_string(all)));
  }

  TEST_CASE("the same output for the same input (no undefined formatting), random strings round-trip") {
    std::mt19937 rng(7);
    for (int k = 0; k < 500; ++k) {
      std::string s(rng() % 40, '\0');
      for (char& c : s) c = char(rng() % 128);  // ASCII, control characters included
      const std::string a = softcut::json_string(s), b = softcut::json_string(s);
      CHECK(a == b);
      CHECK(nlohmann::json::parse(a).get<std::string>() == s);
    }
    CHECK(softcut::json_string("tab\there \"q\" \\ \x01") == "\"tab\\there \\\"q\\\" \\\\ \\u0001\"");
  }
}
