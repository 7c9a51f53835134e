#include "app/check_report.hpp"

#include <cstdio>
#include <pugixml.hpp>

#include "core/atomic_file.hpp"
#include "core/error.hpp"
#include "core/json_text.hpp"
#include "core/printable.hpp"

namespace softcut::app {

namespace {

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

// Code point of a well-formed UTF-8 sequence of n bytes.
char32_t decode(std::string_view s, std::size_t n) {
  const auto b = [&](std::size_t i) { return char32_t(static_cast<unsigned char>(s[i])); };
  if (n == 1) return b(0);
  char32_t cp = b(0) & (0xFF >> (n + 1));
  for (std::size_t i = 1; i < n; ++i) cp = (cp << 6) | (b(i) & 0x3F);
  return cp;
}

bool xml_unwanted(char32_t cp) {
  return (cp >= 0x80 && cp <= 0x9F) || (cp >= 0xFDD0 && cp <= 0xFDEF) || (cp & 0xFFFE) == 0xFFFE;
}

void set(pugi::xml_node node, const char* attribute, const std::string& value) {
  node.append_attribute(attribute).set_value(value.c_str());
}

void write_report(const std::filesystem::path& file, const std::string& text, std::uint64_t max_bytes,
                  const char* what) {
  if (max_bytes > 0 && text.size() > max_bytes)
    fail(file.string(), ": the ", what, " would be ", text.size(), " bytes, over the --max-output limit of ",
         max_bytes, " bytes; raise it or check fewer scenarios at once");
  write_file_atomic(file, text);
}

}  // namespace

std::string xml_safe(std::string_view text, std::size_t max_bytes) {
  std::string out;
  const std::size_t end = std::min(text.size(), max_bytes);
  char buf[16];
  for (std::size_t i = 0; i < end;) {
    const auto c = static_cast<unsigned char>(text[i]);
    const std::size_t n = utf8_sequence_length(text.substr(i, end - i));
    if (n == 0 || (n == 1 && ((c < 0x20 && c != '\t' && c != '\n' && c != '\r') || c == 0x7F))) {
      std::snprintf(buf, sizeof buf, "\\x%02X", unsigned(c));
      out += buf;
      ++i;
      continue;
    }
    const char32_t cp = decode(text.substr(i), n);
    if (xml_unwanted(cp)) {
      std::snprintf(buf, sizeof buf, "\\u{%04X}", unsigned(cp));
      out += buf;
    } else {
      out.append(text.substr(i, n));
    }
    i += n;
  }
  if (end < text.size()) out += "...";
  return out;
}

std::string junit_xml(const std::vector<CheckedScenario>& results, double total_s) {
  int failures = 0, skipped = 0;
  for (const auto& r : results) {
    failures += r.status == CheckedScenario::Status::fail;
    skipped += r.status == CheckedScenario::Status::skipped;
  }
  pugi::xml_document doc;
  pugi::xml_node decl = doc.append_child(pugi::node_declaration);
  set(decl, "version", "1.0");
  set(decl, "encoding", "UTF-8");
  pugi::xml_node suite = doc.append_child("testsuite");
  set(suite, "name", "softcut check");
  set(suite, "tests", std::to_string(results.size()));
  set(suite, "failures", std::to_string(failures));
  set(suite, "errors", "0");
  set(suite, "disabled", "0");
  set(suite, "skipped", std::to_string(skipped));
  set(suite, "time", seconds(total_s));
  for (const auto& r : results) {
    pugi::xml_node tc = suite.append_child("testcase");
    set(tc, "name", xml_safe(r.name));
    set(tc, "classname", xml_safe(r.file.string()));
    set(tc, "time", seconds(r.time_s));
    set(tc, "assertions", std::to_string(r.expectations_total));
    set(tc, "status", r.status == CheckedScenario::Status::skipped ? "notrun" : "run");
    if (r.status == CheckedScenario::Status::fail) {
      pugi::xml_node f = tc.append_child("failure");
      set(f, "message", xml_safe(r.reason));
      std::string body;
      for (const auto& line : r.failures) body += xml_safe(line) + "\n";
      f.append_child(pugi::node_pcdata).set_value(body.c_str());
    } else if (r.status == CheckedScenario::Status::skipped) {
      set(tc.append_child("skipped"), "message", xml_safe(r.reason));
    }
    std::string out;
    for (const auto& e : r.expectations)
      out += xml_safe(cat(e.ok ? "ok    " : "FAIL  ", e.where, " expect '", e.name, "': ",
                          e.reached ? e.message : "not reached (the run ended first)")) + "\n";
    if (r.expectations_total > r.expectations.size())
      out += cat("... ", r.expectations_total - r.expectations.size(), " more expectations (",
                 r.expectations_failed, " of all ", r.expectations_total, " failed)\n");
    if (r.status == CheckedScenario::Status::pass) out += xml_safe(r.detail) + "\n";
    tc.append_child("system-out").append_child(pugi::node_pcdata).set_value(out.c_str());
  }
  struct Sink : pugi::xml_writer {
    std::string text;
    void write(const void* data, size_t size) override { text.append(static_cast<const char*>(data), size); }
  } sink;
  doc.save(sink, "  ", pugi::format_default, pugi::encoding_utf8);
  return sink.text;
}

std::string check_json(const std::vector<CheckedScenario>& results, double total_s) {
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
    s["failures_omitted"] = r.failures_omitted;
    s["time_s"] = r.time_s;
    s["expectations"] = Json::array();
    for (const auto& e : r.expectations)
      s["expectations"].push_back(
          {{"name", e.name}, {"where", e.where}, {"reached", e.reached}, {"ok", e.ok}, {"message", e.message}});
    s["expectations_total"] = r.expectations_total;
    s["expectations_failed"] = r.expectations_failed;
    s["expectations_omitted"] = r.expectations_total - r.expectations.size();
    s["warnings"] = r.warnings;
    s["warnings_total"] = r.warnings_total;
    if (r.compared)
      s["comparison"] = {{"max_diff_m", r.max_diff}, {"scale_m", r.scale},     {"tolerance", r.tolerance},
                         {"frame", r.worst_frame},  {"node", r.worst_node}};
    j["scenarios"].push_back(std::move(s));
  }
  j["passed"] = passed, j["failed"] = failed, j["skipped"] = skipped, j["time_s"] = total_s;
  return json_text(j);
}

void write_junit(const std::filesystem::path& file, const std::vector<CheckedScenario>& results, double total_s,
                 std::uint64_t max_bytes) {
  write_report(file, junit_xml(results, total_s), max_bytes, "JUnit report");
}

void write_check_json(const std::filesystem::path& file, const std::vector<CheckedScenario>& results,
                      double total_s, std::uint64_t max_bytes) {
  write_report(file, check_json(results, total_s), max_bytes, "JSON report");
}

}  // namespace softcut::app
