// engine/core/json_text.cpp: every string becomes valid JSON that reads back
// (well-formed UTF-8 unchanged; other bytes as U+FFFD), whatever its bytes;
// numbers keep the digits asked for, and non-finite ones become null.
#include "core/json_text.hpp"

#include <doctest/doctest.h>

#include <nlohmann/json.hpp>
#include <cmath>
#include <limits>
#include <random>
#include <string>

namespace {
// A string written as a whole JSON document.
std::string json_string(const std::string& s) { return softcut::json_text(softcut::Json(s)); }
}  // namespace

TEST_SUITE("core/json_text") {
  TEST_CASE("every byte value alone and all 256 together give valid JSON") {
    std::string all;
    for (int c = 0; c < 256; ++c) {
      const std::string in(1, char(c));
      all += in;
      const std::string text = json_string(in);
      CAPTURE(c);
      const nlohmann::json j = nlohmann::json::parse(text);  // throws on invalid JSON
      REQUIRE(j.is_string());
      if (c < 0x80) CHECK(j.get<std::string>() == in);
      else CHECK(j.get<std::string>() == "\xEF\xBF\xBD");  // a lone byte >= 0x80 is not UTF-8
    }
    CHECK_NOTHROW((void)nlohmann::json::parse(json_string(all)));
  }

  TEST_CASE("the same output for the same input (no undefined formatting), random strings round-trip") {
    std::mt19937 rng(7);
    for (int k = 0; k < 500; ++k) {
      std::string s(rng() % 40, '\0');
      for (char& c : s) c = char(rng() % 128);  // ASCII, control characters included
      const std::string a = json_string(s), b = json_string(s);
      CHECK(a == b);
      CHECK(nlohmann::json::parse(a).get<std::string>() == s);
    }
    CHECK(json_string("tab\there \"q\" \\ \x01") == "\"tab\\there \\\"q\\\" \\\\ \\u0001\"\n");
  }

  TEST_CASE("numbers keep the significant digits asked for and read back - non-finite ones are null") {
    using softcut::json_number;
    CHECK(json_number(12.3456789, 6).dump() == "12.3457");
    CHECK(json_number(0.1 + 0.2).dump() == "0.3");  // 15 digits: the binary tail is dropped
    CHECK(json_number(0.1 + 0.2, 17).get<double>() == 0.1 + 0.2);
    CHECK(json_number(-2.5e-300).dump() == "-2.5e-300");
    CHECK(json_number(1e21, 6).get<double>() == 1e21);
    CHECK(json_number(std::nan("")).is_null());
    CHECK(json_number(std::numeric_limits<double>::infinity()).is_null());
    CHECK(json_number(-std::numeric_limits<double>::infinity(), 6).is_null());
    std::mt19937_64 rng(11);
    std::uniform_real_distribution<double> expo(-30, 30);
    for (int k = 0; k < 1000; ++k) {
      const double v = std::pow(10.0, expo(rng)) * (k % 2 ? 1 : -1);
      const double back = nlohmann::json::parse(json_number(v, 6).dump()).get<double>();
      CHECK(std::abs(back - v) <= 5e-6 * std::abs(v));
    }
  }
}
