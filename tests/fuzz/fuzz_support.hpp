#pragma once
// Shared by the libFuzzer targets: a private scratch folder per process (on
// /dev/shm when it exists, so per-exec files cost no disk I/O) and the rule
// every target enforces: an input either parses or fails with softcut::Error;
// any other exception, crash, leak, sanitizer report or hang is a finding.
#include <unistd.h>

#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>
#include <string_view>

#include "core/error.hpp"

namespace softcut::fuzz {

inline const std::filesystem::path& scratch() {
  static const std::filesystem::path dir = [] {
    std::error_code ec;
    const std::filesystem::path base = std::filesystem::is_directory("/dev/shm", ec)
                                           ? std::filesystem::path("/dev/shm")
                                           : std::filesystem::temp_directory_path();
    auto d = base / ("softcut-fuzz-" + std::to_string(::getpid()));
    std::filesystem::create_directories(d);
    std::atexit([] {
      std::error_code e;
      std::filesystem::remove_all(scratch(), e);
    });
    return d;
  }();
  return dir;
}

// Writes `bytes` to scratch()/name and returns the path.
inline std::filesystem::path put_file(const std::string& name, std::string_view bytes) {
  const auto p = scratch() / name;
  std::ofstream(p, std::ios::binary | std::ios::trunc).write(bytes.data(), std::streamsize(bytes.size()));
  return p;
}

inline std::string_view as_text(const std::uint8_t* data, std::size_t size) {
  return {reinterpret_cast<const char*>(data), size};
}

// Runs f(); softcut::Error is the expected way to refuse an input.
template <class F>
void expect_clean(F&& f) {
  try {
    f();
  } catch (const softcut::Error&) {
  }
}

}  // namespace softcut::fuzz
