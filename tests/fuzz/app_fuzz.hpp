#pragma once
// What the application reads and writes from untrusted bytes, one entry per
// fuzz target (fuzz_junit, fuzz_reflog, fuzz_sweep_table, fuzz_sweep_plan,
// fuzz_summary); the fuzz targets and hardening/fuzz_regressions both call
// these. An input must be read cleanly or refused with softcut::Error; the
// JUnit writer's output must be well-formed XML whatever the input holds (a
// violation is a crash: __builtin_trap, a finding).
#include <filesystem>
#include <fstream>
#include <pugixml.hpp>
#include <string>
#include <string_view>
#include <vector>

#include "app/check_report.hpp"
#include "app/reference_log.hpp"
#include "app/sweep_merge.hpp"
#include "app/sweep_plan.hpp"
#include "core/printable.hpp"

namespace softcut::fuzz_app {

// Up to n fields of `bytes` separated by NUL (missing ones empty).
inline std::vector<std::string> fields(std::string_view bytes, std::size_t n) {
  std::vector<std::string> f(n);
  for (std::size_t k = 0, at = 0; k < n && at <= bytes.size(); ++k) {
    const std::size_t nul = bytes.find('\0', at);
    const std::size_t end = k + 1 == n || nul == std::string_view::npos ? bytes.size() : nul;
    f[k] = std::string(bytes.substr(at, end - at));
    at = end + 1;
  }
  return f;
}

// XML 1.0 text in UTF-8: every byte in a well-formed sequence, no control
// character but tab, LF, CR, no U+FFFE / U+FFFF.
inline bool xml_chars_only(std::string_view s) {
  for (std::size_t i = 0; i < s.size();) {
    const auto c = static_cast<unsigned char>(s[i]);
    const std::size_t n = utf8_sequence_length(s.substr(i));
    if (n == 0) return false;
    if (n == 1 && c < 0x20 && c != '\t' && c != '\n' && c != '\r') return false;
    if (n == 3 && c == 0xEF && static_cast<unsigned char>(s[i + 1]) == 0xBF &&
        static_cast<unsigned char>(s[i + 2]) >= 0xBE)
      return false;
    i += n;
  }
  return true;
}

// The JUnit writer: fields name, file, reason, failure, expectation name,
// where, message, detail (NUL-separated).
inline void feed_junit(std::string_view bytes) {
  using app::CheckedScenario;
  const std::vector<std::string> f = fields(bytes, 8);
  std::vector<CheckedScenario> results(3);
  results[0].name = f[0], results[0].file = f[1], results[0].reason = f[2], results[0].failures = {f[3], f[2]};
  results[0].status = CheckedScenario::Status::fail;
  results[0].expectations = {{f[4], f[5], true, false, f[6]}, {f[6], f[4], false, false, f[5]}};
  results[0].expectations_total = 2 + bytes.size(), results[0].expectations_failed = bytes.size();
  results[1].name = f[4], results[1].file = f[0], results[1].detail = f[7];
  results[1].status = CheckedScenario::Status::pass;
  results[2].name = f[7], results[2].file = f[6], results[2].reason = f[3];
  results[2].status = CheckedScenario::Status::skipped;
  const std::string xml = app::junit_xml(results, double(bytes.size()));
  if (!xml_chars_only(xml)) __builtin_trap();
  pugi::xml_document doc;
  if (!doc.load_buffer(xml.data(), xml.size(), pugi::parse_minimal | pugi::parse_escapes | pugi::parse_declaration,
                       pugi::encoding_utf8))
    __builtin_trap();
  const pugi::xml_node tc = doc.child("testsuite").child("testcase");
  if (std::string(tc.attribute("name").value()) != app::xml_safe(f[0]) ||
      std::string(tc.child("failure").attribute("message").value()) != app::xml_safe(f[2]))
    __builtin_trap();
}

// The reference-log reader: the input is a reference compared with a small
// log (and its header read alone).
inline void feed_reflog(std::string_view bytes, const std::filesystem::path& dir) {
  static const char* kLog = "frame,time,node,ux,uy,uz\n0,0,1,0,0,-1e-3\n0,0,2,1e-3,0,0\n1,0.1,1,0,0,-2e-3\n1,0.1,2,2e-3,0,0\n";
  std::ofstream(dir / "log.csv", std::ios::binary | std::ios::trunc) << kLog;
  std::ofstream(dir / "s.ref.csv", std::ios::binary | std::ios::trunc).write(bytes.data(), std::streamsize(bytes.size()));
  const app::RunIdentity who{"s", "fnv1a64:0000000000000000", {{"f", "1"}}};
  try {
    app::compare_logs(app::LogFile{dir, "log.csv"}, app::LogFile{dir, "s.ref.csv"}, 1e-6, &who);
  } catch (const Error&) {
  }
  try {
    app::read_reference_header(app::LogFile{dir, "s.ref.csv"});
  } catch (const Error&) {
  }
}

// The sweep table reader (a CSV file).
inline void feed_sweep_table(std::string_view bytes, const std::filesystem::path& dir) {
  std::ofstream(dir / "t.csv", std::ios::binary | std::ios::trunc).write(bytes.data(), std::streamsize(bytes.size()));
  std::vector<std::string> keys;
  try {
    app::read_table(dir / "t.csv", keys);
  } catch (const Error&) {
  }
}

// The sweep plan reader (sweep_plan.json's text); a plan read back writes
// the same plan again.
inline void feed_sweep_plan(std::string_view bytes) {
  try {
    const app::SweepPlan plan = app::parse_plan(std::string(bytes), "sweep_plan.json");
    const app::SweepPlan again = app::parse_plan(app::plan_json(plan), "again.json");
    if (app::plan_json(again) != app::plan_json(plan)) __builtin_trap();
  } catch (const Error&) {
  }
}

// sweep merge's summary reader (a run's summary.json text).
inline void feed_summary(std::string_view bytes) {
  try {
    app::parse_run_summary(std::string(bytes), "summary.json");
  } catch (const Error&) {
  }
}

}  // namespace softcut::fuzz_app
