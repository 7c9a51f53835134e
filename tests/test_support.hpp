#pragma once
// Shared helpers for the doctest suites.
#include <filesystem>
#include <nlohmann/json.hpp>
#include <string>

#include "core/error.hpp"

namespace softcut::test {

// Calls f() and returns the softcut::Error message ("" when f returned).
// Any other exception escapes (the test fails on it).
template <class F>
std::string error_of(F&& f) {
  try {
    f();
    return "";
  } catch (const Error& e) {
    return e.what();
  }
}

inline bool contains(const std::string& s, const std::string& part) { return s.find(part) != std::string::npos; }

// A file's bytes ("" when it cannot be read: the test's next check fails).
std::string slurp(const std::filesystem::path& file);

// A JSON document softcut wrote, parsed strictly: invalid JSON and an object
// with the same key twice (which nlohmann would otherwise take, keeping the
// last) throw std::runtime_error naming the key. Reading files that the
// engine writes through the same library, the tests still check what a
// stricter reader would see.
nlohmann::ordered_json parse_json(const std::string& text);
nlohmann::ordered_json read_json(const std::filesystem::path& file);

// Test data folder (tests/data) and a fresh, empty scratch folder per name.
std::filesystem::path data_dir();
std::filesystem::path scratch_dir(const std::string& name);

}  // namespace softcut::test
