// app/check_report.cpp: the JUnit XML (pugixml) and JSON reports of
// softcut check, whatever bytes the names and messages hold.
#include "app/check_report.hpp"

#include <doctest/doctest.h>

#include <fstream>
#include <pugixml.hpp>

#include "cli_test_support.hpp"
#include "core/printable.hpp"
#include "test_support.hpp"

namespace fs = std::filesystem;
using namespace softcut::app;
using softcut::test::contains;

namespace {

// Every byte value, and the code points XML refuses or discourages.
std::string hostile() {
  std::string s;
  for (int c = 0; c < 256; ++c) s += char(c);
  return s + "\xEF\xBF\xBE \xEF\xBF\xBF \xEF\xB7\x90 \xF4\x8F\xBF\xBF \xC2\x85 \xED\xA0\x80 \xC0\xAF ]]> <!-- &amp;";
}

bool xml_valid(const fs::path& file) {
  const auto lint = softcut::test::run_cli_raw("xmllint --noout --schema '" +
                                               softcut::test::source("tests/data/junit.xsd") + "' '" + file.string() + "'");
  INFO(lint.output);
  return lint.status == 0;
}

}  // namespace

TEST_SUITE("app/check_report") {
  TEST_CASE("xml_safe: UTF-8 of allowed characters stays, everything else is shown escaped") {
    CHECK(xml_safe("plain é ✓ 𝄞 <&>\"'\t\n\r") == "plain é ✓ 𝄞 <&>\"'\t\n\r");  // pugixml escapes <&>"
    CHECK(xml_safe(std::string("a\0b", 3)) == "a\\x00b");
    CHECK(xml_safe("\x1b[31m\x7f") == "\\x1B[31m\\x7F");
    CHECK(xml_safe("\xff\xfe") == "\\xFF\\xFE");
    CHECK(xml_safe("\xC3\x28") == "\\xC3(");              // a broken sequence: its bytes
    CHECK(xml_safe("\xED\xA0\x80") == "\\xED\\xA0\\x80");  // a surrogate is not UTF-8
    CHECK(xml_safe("a\xEF\xBF\xBE" "b\xEF\xBF\xBF") == "a\\u{FFFE}b\\u{FFFF}");
    CHECK(xml_safe("\xEF\xB7\x90") == "\\u{FDD0}");
    CHECK(xml_safe("\xF4\x8F\xBF\xBF") == "\\u{10FFFF}");
    CHECK(xml_safe("\xC2\x85") == "\\u{0085}");  // C1 control (NEL)
    CHECK(xml_safe("abcdef", 3) == "abc...");
    const std::string safe = xml_safe(hostile());
    for (std::size_t i = 0; i < safe.size();) {  // well-formed UTF-8 without control bytes but tab, LF, CR
      const auto c = static_cast<unsigned char>(safe[i]);
      const std::size_t n = softcut::utf8_sequence_length(std::string_view(safe).substr(i));
      REQUIRE(n > 0);
      CHECK((c >= 0x20 || c == '\t' || c == '\n' || c == '\r'));
      CHECK(c != 0x7F);
      i += n;
    }
  }

  TEST_CASE("the JUnit report validates against the schema whatever the names and messages hold") {
    const fs::path dir = softcut::test::scratch_dir("check_report_xml");
    std::vector<CheckedScenario> results(3);
    results[0].file = "scenarios/" + hostile() + ".lua";
    results[0].name = hostile();
    results[0].status = CheckedScenario::Status::fail;
    results[0].reason = hostile();
    results[0].failures = {hostile(), "second"};
    results[0].expectations = {{hostile(), "s.lua:3", true, false, hostile()}};
    results[0].expectations_total = 250, results[0].expectations_failed = 250;
    results[1].file = "ok.lua", results[1].name = "ok", results[1].status = CheckedScenario::Status::pass;
    results[1].detail = "3 frames";
    results[2].file = "mod.lua", results[2].name = "mod", results[2].status = CheckedScenario::Status::skipped;
    results[2].reason = "makes no scenario";
    write_junit(dir / "r.xml", results, 1.5);
    CHECK(xml_valid(dir / "r.xml"));
    pugi::xml_document doc;
    REQUIRE(doc.load_file((dir / "r.xml").c_str()));
    const pugi::xml_node suite = doc.child("testsuite");
    CHECK(std::string(suite.attribute("tests").value()) == "3");
    CHECK(std::string(suite.attribute("failures").value()) == "1");
    CHECK(std::string(suite.attribute("skipped").value()) == "1");
    const pugi::xml_node bad = suite.child("testcase");
    CHECK(std::string(bad.attribute("name").value()) == xml_safe(hostile()));
    CHECK(std::string(bad.attribute("assertions").value()) == "250");
    CHECK(contains(bad.child("system-out").text().get(), "... 249 more expectations (250 of all 250 failed)"));
    CHECK(std::string(bad.child("failure").attribute("message").value()) == xml_safe(hostile()));
    // --max-output bounds it.
    CHECK(contains(softcut::test::error_of([&] { write_junit(dir / "small.xml", results, 1.5, 100); }),
                   "small.xml: the JUnit report would be"));
    CHECK(!fs::exists(dir / "small.xml"));
  }

  TEST_CASE("the JSON report: the kept expectations, their counts, valid JSON whatever the bytes") {
    const fs::path dir = softcut::test::scratch_dir("check_report_json");
    std::vector<CheckedScenario> results(1);
    results[0].file = "x.lua", results[0].name = hostile(), results[0].reason = hostile();
    results[0].expectations = {{"e", "x.lua:1", true, false, hostile()}};
    results[0].expectations_total = 7, results[0].expectations_failed = 3, results[0].failures_omitted = 2;
    write_check_json(dir / "r.json", results, 2);
    const auto j = softcut::test::read_json(dir / "r.json");
    CHECK(j["failed"] == 1);
    CHECK(j["scenarios"][0]["expectations_total"] == 7);
    CHECK(j["scenarios"][0]["expectations_failed"] == 3);
    CHECK(j["scenarios"][0]["expectations_omitted"] == 6);
    CHECK(j["scenarios"][0]["failures_omitted"] == 2);
    CHECK(!j["scenarios"][0].contains("comparison"));  // none ran
  }
}
