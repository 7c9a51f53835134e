// app/option_values.cpp: the validators CLI11 runs on option values before
// converting them; each names the value and what it expected.
#include "app/option_values.hpp"

#include <doctest/doctest.h>

#include <cmath>
#include <sstream>

#include "backend/spec.hpp"

using namespace softcut::app;

namespace {

// The validator's verdict on `text` ("" when accepted) and the text it leaves.
std::pair<std::string, std::string> run(const CLI::Validator& v, std::string text) {
  const std::string error = v(text);
  return {error, text};
}

}  // namespace

TEST_SUITE("app/option_values") {
  TEST_CASE("whole numbers: the whole text, within the range") {
    const CLI::Validator v = whole_number(0, 100);
    for (const char* ok : {"0", "7", "100"}) CHECK(run(v, ok).first == "");
    for (const char* bad : {"", "-1", "101", "1.5", "7x", " 7", "+7", "0x10", "99999999999999999999"})
      CHECK(run(v, bad).first == std::string(bad) + ": expected a whole number from 0 to 100");
    CHECK(run(whole_number(1, 5), "0").first == "0: expected a whole number from 1 to 5");
    CHECK(run(v, "a\x1b[31m").first == "a\\x1B[31m: expected a whole number from 0 to 100");  // escaped
  }

  TEST_CASE("seconds, bytes, numbers in open intervals") {
    for (const char* ok : {"0", "0.5", "3600", "1e7"}) CHECK(run(seconds_limit(), ok).first == "");
    for (const char* bad : {"-1", "1e8", "nan", "inf", "5s", ""})
      CHECK(run(seconds_limit(), bad).first == std::string(bad) + ": expected seconds from 0 (no limit) to 10000000");
    CHECK(run(byte_count(), "3M") == std::pair<std::string, std::string>{"", "3145728"});
    CHECK(run(byte_count(), "1.5k") == std::pair<std::string, std::string>{"", "1536"});
    CHECK(run(byte_count(), "8G").second == "8589934592");
    CHECK(run(byte_count(), "0").second == "0");
    for (const char* bad : {"3Q", "-1", "G", "1e30", "nan"})
      CHECK(run(byte_count(), bad).first ==
            std::string(bad) + ": expected a number of bytes (0: no limit), optionally with K, M or G (e.g. 8G)");
    const CLI::Validator r = open_interval(0, 1, "a radius in m");
    CHECK(run(r, "0.5").first == "");
    for (const char* bad : {"0", "1", "-1", "5mm", "nan"})
      CHECK(run(r, bad).first == std::string(bad) + ": expected a radius in m greater than 0 and below 1");
    CHECK(run(open_interval(0, INFINITY, "a bandwidth"), "1e6").first == "");
    CHECK(run(open_interval(0, INFINITY, "a bandwidth"), "inf").first == "inf: expected a bandwidth greater than 0");
    CHECK(run(finite_number(-1, 1, "a fraction"), "2").first == "2: expected a fraction from -1 to 1");
  }

  TEST_CASE("names: backends, one_of lists, key=value, WxH") {
    CHECK(run(backend_name(), "cpu") ==
          std::pair<std::string, std::string>{"", std::to_string(int(softcut::backend::Backend::cpu))});
    CHECK(run(backend_name(), "auto").second == std::to_string(int(softcut::backend::Backend::automatic)));
    CHECK(run(backend_name(), "CPU").first == "CPU: expected auto, cpu, gpu, direct or monolithic");
    const CLI::Validator s = one_of({{"dense", 1}, {"product", 2}, {"factor", 3}});
    CHECK(run(s, "product") == std::pair<std::string, std::string>{"", "2"});
    CHECK(run(s, "sparse").first == "sparse: expected dense, product or factor");
    for (const char* ok : {"a=1", "a=", "a=b=c"}) CHECK(run(key_value(), ok).first == "");
    for (const char* bad : {"a", "=1", ""})
      CHECK(run(key_value(), bad).first == std::string(bad) + ": expected key=value (e.g. --set force=0.5)");
    for (const char* ok : {"640x480", "1x1", "16384x16384"}) CHECK(run(frame_size(), ok).first == "");
    for (const char* bad : {"64", "0x10", "16385x1", "axb", "640x", "x480", "640x480x3"})
      CHECK(run(frame_size(), bad).first ==
            std::string(bad) + ": expected WIDTHxHEIGHT in pixels, each from 1 to 16384 (e.g. 640x480)");
    std::istringstream in("640x480");
    FrameSize size;
    in >> size;
    CHECK(size.width == 640);
    CHECK(size.height == 480);
  }
}
