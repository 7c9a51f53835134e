#pragma once
// Shared helpers for the doctest suites.
#include <filesystem>
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

// Test data folder (tests/data) and a fresh, empty scratch folder per name.
std::filesystem::path data_dir();
std::filesystem::path scratch_dir(const std::string& name);

}  // namespace softcut::test
