#pragma once
// What `softcut check` found per scenario, and the machine-readable reports a
// CI system reads: JUnit XML (the shape of ctest's --output-junit: one
// <testsuite>, one <testcase> per scenario, expectations as its assertions)
// and JSON (the same facts, field names in docs/outputs.md "softcut check").
#include <filesystem>
#include <string>
#include <vector>

namespace softcut::app {

struct CheckedExpectation {
  std::string name, where;  // "scenario.lua:40"
  bool reached = false;     // false: the run ended before its time
  bool ok = false;
  std::string message;      // what was measured, or the check's message
};

struct CheckedScenario {
  std::filesystem::path file;
  std::string name;          // softcut.scenario{ name }; the file's stem when the script failed first
  enum class Status { pass, fail, skipped } status = Status::fail;
  std::string reason;        // fail: first line of why; skipped: why
  std::string detail;        // pass: frames, expectations, largest difference, time
  std::vector<std::string> failures;  // fail: every failed expectation and the comparison, one line each
  std::vector<CheckedExpectation> expectations;
  double time_s = 0;         // wall-clock of this scenario
  bool compared = false;     // a reference comparison ran
  double max_diff = 0, scale = 0, tolerance = 0;  // m, m, relative
  long worst_frame = -1, worst_node = -1;          // where max_diff is (-1: none)
};

// Writes `file` atomically. Throws softcut::Error when it cannot.
void write_junit(const std::filesystem::path& file, const std::vector<CheckedScenario>& results, double total_s);
void write_check_json(const std::filesystem::path& file, const std::vector<CheckedScenario>& results,
                      double total_s);

}  // namespace softcut::app
