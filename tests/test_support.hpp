#pragma once
// Shared helpers for the doctest suites.
#include <filesystem>
#include <string>

namespace softcut::test {

// Test data folder (tests/data) and a fresh, empty scratch folder per name.
std::filesystem::path data_dir();
std::filesystem::path scratch_dir(const std::string& name);

}  // namespace softcut::test
