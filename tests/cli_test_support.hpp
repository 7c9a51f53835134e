#pragma once
// Running the softcut executable (SOFTCUT_BIN) from tests.
#include <sys/wait.h>

#include <array>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

#include "test_support.hpp"

namespace softcut::test {

struct CliResult {
  int status = -1;     // exit status
  std::string output;  // stdout and stderr together
};

// Runs `softcut ARGS` in `cwd` (default: the source folder), capturing output;
// `env` ("NAME=value ...") goes before the program.
// Runs a shell command line, capturing stdout and stderr together.
inline CliResult run_cli_raw(const std::string& command) {
  CliResult r;
  FILE* p = popen((command + " 2>&1").c_str(), "r");
  if (!p) return r;
  std::array<char, 4096> buf;
  size_t n;
  while ((n = fread(buf.data(), 1, buf.size(), p)) > 0) r.output.append(buf.data(), n);
  const int st = pclose(p);
  r.status = WIFEXITED(st) ? WEXITSTATUS(st) : -1;
  return r;
}

inline CliResult run_cli(const std::string& args, const std::filesystem::path& cwd = SOFTCUT_SOURCE_DIR,
                         const std::string& env = "") {
  return run_cli_raw("cd '" + cwd.string() + "' && " + env + " '" SOFTCUT_BIN "' " + args);
}

inline std::string source(const std::string& rel) { return (std::filesystem::path(SOFTCUT_SOURCE_DIR) / rel).string(); }


}  // namespace softcut::test
