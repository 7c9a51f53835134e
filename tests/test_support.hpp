#pragma once
// Shared helpers for the doctest suites.
#include <filesystem>
#include <nlohmann/json.hpp>
#include <map>
#include <string>
#include <vector>

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

// An independent reader's view of a .vtu file: tests/data/read_vtu_meshio.py
// run by Debian's python3 with python3-meshio (scripts/install-deps.sh
// --test), by array name ("points", "tetra", "point.<name>", "cell.<name>"),
// floats as their exact bits. Throws std::runtime_error saying what to
// install when python3 or meshio is missing, or quoting the reader's error.
struct ForeignArrays {
  std::map<std::string, std::vector<double>> arrays;
  int cell_blocks = 0, tetra_blocks = 0;
};
ForeignArrays read_vtu_with_meshio(const std::filesystem::path& vtu);

// Test data folder (tests/data) and a fresh, empty scratch folder per name.
std::filesystem::path data_dir();
std::filesystem::path scratch_dir(const std::string& name);

}  // namespace softcut::test
