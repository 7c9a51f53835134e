#include "app/option_values.hpp"

#include <charconv>
#include <cmath>
#include <istream>

#include "backend/spec.hpp"
#include "core/error.hpp"
#include "core/printable.hpp"

namespace softcut::app {

namespace {

template <class T>
bool whole_text(const std::string& s, T& out) {
  const auto [end, ec] = std::from_chars(s.data(), s.data() + s.size(), out);
  return !s.empty() && ec == std::errc() && end == s.data() + s.size();
}

// The number at the start of s; *used: its length (0: none).
double leading_number(const std::string& s, std::size_t* used) {
  double v = 0;
  const auto [end, ec] = std::from_chars(s.data(), s.data() + s.size(), v);
  *used = ec == std::errc() ? std::size_t(end - s.data()) : 0;
  return v;
}

std::string shown(const std::string& s) { return printable(s, 80); }

}  // namespace

CLI::Validator whole_number(long long lo, long long hi) {
  return CLI::Validator(
      [lo, hi](std::string& s) -> std::string {
        long long v = 0;
        if (whole_text(s, v) && v >= lo && v <= hi) return "";
        return cat(shown(s), ": expected a whole number from ", lo, " to ", hi);
      },
      "");
}

CLI::Validator finite_number(double lo, double hi, const std::string& unit) {
  return CLI::Validator(
      [lo, hi, unit](std::string& s) -> std::string {
        std::size_t used = 0;
        const double v = leading_number(s, &used);
        if (used == s.size() && !s.empty() && v >= lo && v <= hi) return "";
        return cat(shown(s), ": expected ", unit, " from ", lo, " to ", hi);
      },
      "");
}

CLI::Validator open_interval(double lo, double hi, const std::string& unit) {
  return CLI::Validator(
      [lo, hi, unit](std::string& s) -> std::string {
        std::size_t used = 0;
        const double v = leading_number(s, &used);
        if (used == s.size() && !s.empty() && std::isfinite(v) && v > lo && v < hi) return "";
        return cat(shown(s), ": expected ", unit, " greater than ", lo, std::isfinite(hi) ? cat(" and below ", hi) : "");
      },
      "");
}

CLI::Validator one_of(const std::vector<std::pair<std::string, int>>& names) {
  std::string list;
  for (size_t i = 0; i < names.size(); ++i)
    list += (i == 0 ? "" : i + 1 == names.size() ? " or " : ", ") + names[i].first;
  return CLI::Validator(
      [names, list](std::string& s) -> std::string {
        for (const auto& [name, value] : names)
          if (s == name) {
            s = std::to_string(value);
            return "";
          }
        return cat(shown(s), ": expected ", list);
      },
      "");
}

CLI::Validator seconds_limit() {
  return CLI::Validator(
      [](std::string& s) -> std::string {
        std::size_t used = 0;
        const double v = leading_number(s, &used);
        if (used == s.size() && !s.empty() && v >= 0 && v <= 1e7) return "";
        return cat(shown(s), ": expected seconds from 0 (no limit) to 10000000");
      },
      "");
}

CLI::Validator byte_count() {
  return CLI::Validator(
      [](std::string& s) -> std::string {
        std::size_t used = 0;
        const double v = leading_number(s, &used);
        const std::string suffix = s.substr(used);
        double unit = 1;
        if (suffix == "K" || suffix == "k") unit = 1 << 10;
        else if (suffix == "M") unit = 1 << 20;
        else if (suffix == "G") unit = double(1 << 30);
        else if (!suffix.empty()) used = 0;
        if (used == 0 || !(v >= 0) || v * unit > 1e18)
          return cat(shown(s), ": expected a number of bytes (0: no limit), optionally with K, M or G (e.g. 8G)");
        s = std::to_string(std::uint64_t(v * unit));
        return "";
      },
      "");
}

CLI::Validator backend_name() {
  return CLI::Validator(
      [](std::string& s) -> std::string {
        try {
          s = std::to_string(int(backend::parse_backend(s)));
          return "";
        } catch (const Error&) {
          return cat(shown(s), ": expected auto, cpu, gpu, direct or monolithic");
        }
      },
      "");
}

CLI::Validator key_value() {
  return CLI::Validator(
      [](std::string& s) -> std::string {
        const auto eq = s.find('=');
        if (eq != std::string::npos && eq > 0) return "";
        return cat(shown(s), ": expected key=value (e.g. --set force=0.5)");
      },
      "");
}

CLI::Validator frame_size() {
  return CLI::Validator(
      [](std::string& s) -> std::string {
        const auto x = s.find('x');
        int w = 0, h = 0;
        if (x != std::string::npos && whole_text(s.substr(0, x), w) && whole_text(s.substr(x + 1), h) && w >= 1 &&
            w <= 16384 && h >= 1 && h <= 16384)
          return "";
        return cat(shown(s), ": expected WIDTHxHEIGHT in pixels, each from 1 to 16384 (e.g. 640x480)");
      },
      "");
}

std::istream& operator>>(std::istream& in, FrameSize& size) {
  char x = 0;
  in >> size.width >> x >> size.height;
  if (x != 'x') in.setstate(std::ios::failbit);
  return in;
}

}  // namespace softcut::app
