#pragma once
// What `softcut check` found per scenario, and the machine-readable reports a
// CI system reads: JUnit XML (the shape of ctest's --output-junit: one
// <testsuite>, one <testcase> per scenario, expectations as its assertions)
// and JSON (the same facts, field names in docs/outputs.md "softcut check").
//
// A scenario may declare thousands of expectations and its script chooses
// their messages: what is held per scenario is bounded (the first
// kKeptExpectations in full, then counts), and so are the reports.
#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <string>
#include <string_view>
#include <vector>

namespace softcut::app {

// Expectations kept in full per scenario (the reports list these); the
// failure lines of one scenario kept (the console prints these).
constexpr std::size_t kKeptExpectations = 100;
constexpr std::size_t kKeptFailures = 20;

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
  std::vector<std::string> failures;  // fail: every other failure, one line each: the first kKeptFailures - 1
                                      // failed expectations, a count of the rest, the comparison
  std::size_t failures_omitted = 0;   // failed expectations not listed
  std::vector<CheckedExpectation> expectations;  // the first kKeptExpectations
  std::vector<std::string> warnings;  // the run's (each with its [code] when it has one): the first kKeptFailures
  std::size_t warnings_total = 0;
  bool warnings_failed = false;       // --warnings-as-errors failed it (the warnings are among `failures`)
  std::size_t expectations_total = 0, expectations_failed = 0;  // all of them
  double time_s = 0;         // wall-clock of this scenario
  bool compared = false;     // a reference comparison ran
  double max_diff = 0, scale = 0, tolerance = 0;  // m, m, relative
  long worst_frame = -1, worst_node = -1;          // where max_diff is (-1: none)
};

// Text as XML 1.0 character data in UTF-8: well-formed UTF-8 of characters
// XML allows stays as it is; bytes that are not UTF-8, control characters
// (but tab, newline, return) and DEL become "\xNN"; Unicode noncharacters
// (U+FFFE, U+FFFF, U+FDD0..U+FDEF, U+nFFFE/F) and C1 controls become
// "\u{XXXX}". At most `max_bytes` of the input are shown ("..." marks a cut).
std::string xml_safe(std::string_view text, std::size_t max_bytes = 1 << 20);

// The JUnit XML document (written with pugixml; every string through xml_safe).
std::string junit_xml(const std::vector<CheckedScenario>& results, double total_s);
std::string check_json(const std::vector<CheckedScenario>& results, double total_s);

// Writes `file` atomically. Throws softcut::Error when it cannot, or when
// the report would exceed `max_bytes` (--max-output; 0: no limit).
void write_junit(const std::filesystem::path& file, const std::vector<CheckedScenario>& results, double total_s,
                 std::uint64_t max_bytes = 0);
void write_check_json(const std::filesystem::path& file, const std::vector<CheckedScenario>& results,
                      double total_s, std::uint64_t max_bytes = 0);

}  // namespace softcut::app
