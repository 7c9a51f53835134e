#pragma once
// CLI11 validators for softcut's option values: CLI11 converts each value to
// its option's type, and these check (and where needed normalise) the text
// first, so every command reads typed, checked values and the same value is
// refused with the same words everywhere. A validator's message starts with
// the value; Options::parse prints it after the option's name:
//   softcut run: --frames lots: expected a whole number from 0 to 100000000 (see softcut run --help)
#include <CLI/CLI.hpp>
#include <iosfwd>
#include <string>
#include <utility>
#include <vector>

namespace softcut::app {

// A whole number from lo to hi.
CLI::Validator whole_number(long long lo, long long hi);
// A finite number from lo to hi; `unit` names it in the message ("seconds").
CLI::Validator finite_number(double lo, double hi, const std::string& unit = "a number");
// A finite number greater than lo and below hi (hi may be infinite).
CLI::Validator open_interval(double lo, double hi, const std::string& unit);
// One of `names`: normalised to its number, so an enum option takes it.
CLI::Validator one_of(const std::vector<std::pair<std::string, int>>& names);
// Seconds from 0 (no limit) to 10^7.
CLI::Validator seconds_limit();
// Bytes, optionally with a K, M or G suffix (powers of 1024): normalised to
// the whole number of bytes; 0 means no limit. The normalising validators
// (this, backend_name, one_of) go in ->transform(), the others in ->check().
CLI::Validator byte_count();
// auto, cpu, gpu, direct or monolithic (backend::parse_backend): normalised
// to the enum's number, so an option of type backend::Backend takes it.
CLI::Validator backend_name();
// key=value with a non-empty key (--set).
CLI::Validator key_value();

// A rendered frame's size, "WxH" in pixels (1..16384 each): --size.
struct FrameSize {
  int width = 0, height = 0;
};
CLI::Validator frame_size();
// CLI11 reads a FrameSize through this (after frame_size() checked the text).
std::istream& operator>>(std::istream& in, FrameSize& size);

}  // namespace softcut::app
