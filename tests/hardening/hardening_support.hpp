#pragma once
// Helpers for the resource-limit tests: peak-RSS accounting, scratch files,
// a child process with resource limits, and the softcut executable.
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <array>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <functional>
#include <string>

#include "core/error.hpp"
#include "test_support.hpp"

namespace softcut::hardening {

// Peak resident set size of this process so far, bytes.
inline long long peak_rss_bytes() {
  rusage u{};
  getrusage(RUSAGE_SELF, &u);
  return (long long)u.ru_maxrss * 1024;
}

inline std::filesystem::path put_file(const std::filesystem::path& p, const std::string& bytes) {
  std::ofstream(p, std::ios::binary | std::ios::trunc) << bytes;
  return p;
}

using test::contains;
using test::error_of;

// Runs f() in a forked child after `limit` (e.g. RLIMIT_FSIZE) is set; returns
// the child's exit status (f's return value), or 128 + signal.
inline int in_child(int resource, rlim_t limit, const std::function<int()>& f) {
  std::fflush(nullptr);
  const pid_t pid = ::fork();
  if (pid == 0) {
    const rlimit r{limit, limit + 1};  // soft: the signal (SIGXCPU, SIGXFSZ); hard: SIGKILL
    ::setrlimit(resource, &r);
    int rc = 99;
    try {
      rc = f();
    } catch (...) {
      rc = 98;
    }
    std::fflush(nullptr);
    ::_exit(rc);
  }
  int st = 0;
  ::waitpid(pid, &st, 0);
  return WIFEXITED(st) ? WEXITSTATUS(st) : 128 + WTERMSIG(st);
}

// Files below `dir` whose names end in `suffix` (leftover temporaries).
inline int count_files(const std::filesystem::path& dir, const std::string& suffix) {
  int n = 0;
  std::error_code ec;
  for (const auto& e : std::filesystem::recursive_directory_iterator(dir, ec)) {
    const std::string s = e.path().filename().string();
    if (s.size() >= suffix.size() && s.compare(s.size() - suffix.size(), suffix.size(), suffix) == 0) ++n;
  }
  return n;
}

struct CliResult {
  int status = -1;     // exit status
  std::string output;  // stdout and stderr together
};

// Runs `prefix softcut args` through the shell in `cwd`, capturing output.
inline CliResult run_softcut(const std::string& args, const std::filesystem::path& cwd, const std::string& prefix = "") {
  const std::string cmd = "cd '" + cwd.string() + "' && " + prefix + " '" SOFTCUT_BIN "' " + args + " 2>&1";
  CliResult r;
  FILE* p = ::popen(cmd.c_str(), "r");
  if (!p) return r;
  std::array<char, 4096> buf;
  size_t n;
  while ((n = std::fread(buf.data(), 1, buf.size(), p)) > 0) r.output.append(buf.data(), n);
  const int st = ::pclose(p);
  r.status = WIFEXITED(st) ? WEXITSTATUS(st) : -1;
  return r;
}

}  // namespace softcut::hardening
