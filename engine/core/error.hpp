#pragma once
// Errors and warnings. Every user-facing failure is a softcut::Error whose
// message already says where (file:line, element or node id) and how to fix it;
// the CLI prints it on one line and exits non-zero.
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

namespace softcut {

class Error : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// A command line the program cannot use (unknown option, bad value): the
// CLI exits with status 2 for it, 1 for every other Error.
class UsageError : public Error {
 public:
  using Error::Error;
};

// The run's wall-clock limit (--timeout) ended it: exit status 124.
class TimeoutError : public Error {
 public:
  using Error::Error;
};

// cat("a", 1, 'b') -> "a1b": message building without <format> (GCC 12).
template <class... Args>
std::string cat(const Args&... args) {
  std::ostringstream os;
  os.precision(12);
  (os << ... << args);
  return os.str();
}

template <class... Args>
[[noreturn]] void fail(const Args&... args) {
  throw Error(cat(args...));
}

template <class... Args>
[[noreturn]] void usage_fail(const Args&... args) {
  throw UsageError(cat(args...));
}

// Non-fatal findings collected by a stage and reported by the caller
// (CLI prints them, summary.json lists them). No global sink.
struct Diagnostics {
  std::vector<std::string> warnings;
  template <class... Args>
  void warn(const Args&... args) { warnings.push_back(cat(args...)); }
};

}  // namespace softcut
