#include "app/check_report.hpp"


#include <cstdio>
#include <sstream>

#include "core/atomic_file.hpp"
#include "core/error.hpp"
#include "core/json_text.hpp"

namespace softcut::app {

namespace {

// XML attribute / text escaping; control characters XML 1.0 forbids become
// spaces (a script's message may hold any byte).
std::string xml(const std::string& s) {
  std::string out;
  for (const char ch : s) {
    const unsigned char c = static_cast<unsigned char>(ch);
    switch (ch) {
      case '&': out += "&amp;"; break;
      case '<': out += "&lt;"; break;
      case '>': out += "&gt;"; break;
      case '"': out += "&quot;"; break;
      case '\'': out += "&apos;"; break;
      default: out += (c < 0x20 && ch != '\n' && ch != '\t') ? ' ' : ch;
    }
  }
  return out;
}

std::string seconds(double s) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.3f", s);
  return buf;
}

const char* to_string(CheckedScenario::Status s) {
  switch (s) {
    case CheckedScenario::Status::pass: return "pass";
    case CheckedScenario::Status::fail: return "fail";
    case CheckedScenario::Status::skipped: return "skipped";
  }
  return "?";
}

}  // namespace

void write_junit(const std::filesystem::path& file, const std::vector<CheckedScenario>& results, double total_s) {
  int failures = 0, skipped = 0;
  for (const auto& r : results) {
    failures += r.status == CheckedScenario::Status::fail;
    skipped += r.status == CheckedScenario::Status::skipped;
  }
  std::ostringstream x;
  x << "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n"
    << "<testsuite name=\"softcut check\" tests=\"" << results.size() << "\" failures=\"" << failures
    << "\" errors=\"0\" disabled=\"0\" skipped=\"" << skipped << "\" time=\"" << seconds(total_s) << "\">\n";
  for (const auto& r : results) {
    x << "  <testcase name=\"" << xml(r.name) << "\" classname=\"" << xml(r.file.string()) << "\" time=\""
      << seconds(r.time_s) << "\" assertions=\"" << r.expectations.size() << "\" status=\""
      << (r.status == CheckedScenario::Status::skipped ? "notrun" : "run") << "\">\n";
    if (r.status == CheckedScenario::Status::fail) {
      x << "    <failure message=\"" << xml(r.reason) << "\">";
      for (const auto& f : r.failures) x << xml(f) << "\n";
      x << "</failure>\n";
    } else if (r.status == CheckedScenario::Status::skipped) {
      x << "    <skipped message=\"" << xml(r.reason) << "\"/>\n";
    }
    x << "    <system-out>";
    for (const auto& e : r.expectations)
      x << xml(cat(e.ok ? "ok    " : "FAIL  ", e.where, " expect '", e.name, "': ",
                   e.reached ? e.message : "not reached (the run ended first)"))
        << "\n";
    if (r.status == CheckedScenario::Status::pass) x << xml(r.detail) << "\n";
    x << "</system-out>\n  </testcase>\n";
  }
  x << "</testsuite>\n";
  write_file_atomic(file, x.str());
}

void write_check_json(const std::filesystem::path& file, const std::vector<CheckedScenario>& results,
                      double total_s) {
  Json j;
  int passed = 0, failed = 0, skipped = 0;
  j["scenarios"] = Json::array();
  for (const auto& r : results) {
    passed += r.status == CheckedScenario::Status::pass;
    failed += r.status == CheckedScenario::Status::fail;
    skipped += r.status == CheckedScenario::Status::skipped;
    Json s;
    s["file"] = r.file.string();
    s["name"] = r.name;
    s["status"] = to_string(r.status);
    s["reason"] = r.reason;
    s["failures"] = r.failures;
    s["time_s"] = r.time_s;
    s["expectations"] = Json::array();
    for (const auto& e : r.expectations)
      s["expectations"].push_back(
          {{"name", e.name}, {"where", e.where}, {"reached", e.reached}, {"ok", e.ok}, {"message", e.message}});
    if (r.compared)
      s["comparison"] = {{"max_diff_m", r.max_diff}, {"scale_m", r.scale},     {"tolerance", r.tolerance},
                         {"frame", r.worst_frame},  {"node", r.worst_node}};
    j["scenarios"].push_back(std::move(s));
  }
  j["passed"] = passed, j["failed"] = failed, j["skipped"] = skipped, j["time_s"] = total_s;
  write_file_atomic(file, json_text(j));
}

}  // namespace softcut::app
