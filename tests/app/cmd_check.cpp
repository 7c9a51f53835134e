// app/cmd_check.cpp (+ reference_log.cpp) through the real executable.
#include <doctest/doctest.h>

#include <fstream>
#include <map>
#include <nlohmann/json.hpp>
#include <set>

#include "app/reference_log.hpp"
#include "core/warning.hpp"
#include "cli_test_support.hpp"

namespace fs = std::filesystem;
using softcut::test::contains;
using softcut::test::run_cli;
using softcut::test::slurp;

namespace {

// A small fast scenario: a bar pulled at its tip by `f` N (a parameter),
// with one expectation `expect` (a Lua boolean expression of f, the frame)
// and `extra` lines before the end.
void write_bar(const fs::path& file, const std::string& name, const std::string& expect = "true",
               const std::string& extra = "") {
  std::ofstream(file) << "local P = softcut.params{ f = 0.01 }\n"
                         "local s = softcut.scenario{ name = '" << name << "', duration = 0.2, fps = 10 }\n"
                         "s:mesh{ generate = 'box', options = { max = { 0.1, 0.02, 0.02 }, nx = 5, ny = 2, nz = 2 } }\n"
                         "s:material{ young = 5e3, poisson = 0.4 }\n"
                         "s:fix{ nodes = softcut.select.box{ min = { -1, -1, -1 }, max = { 0, 1, 1 } } }\n"
                         "s:load{ name = 'tip', nodes = softcut.select.box{ min = { 0.1, -1, -1 }, max = { 1, 1, 1 } },\n"
                         "        force = { 0, 0, -P.f } }\n"
                         "s:expect{ name = 'holds', at = 0.2, check = function(f) return "
                      << expect << ", ('f = %g'):format(P.f) end }\n"
                      << extra << "return s\n";
}

// Verdict and file of each scenario line ("PASS  file", "FAIL  file", "SKIP  file").
std::vector<std::string> verdicts(const std::string& out) {
  std::vector<std::string> v;
  std::istringstream ss(out);
  for (std::string line; std::getline(ss, line);)
    if (line.rfind("PASS  ", 0) == 0 || line.rfind("FAIL  ", 0) == 0 || line.rfind("SKIP  ", 0) == 0)
      v.push_back(line.substr(0, line.find_first_of(" :", 6)));
  return v;
}

// A copy of scenarios/<name>.lua (+ mesh folder) in a scratch folder.
fs::path copy_scenario(const std::string& dir_name, const std::string& name) {
  const fs::path dir = softcut::test::scratch_dir(dir_name);
  fs::copy_file(softcut::test::source("scenarios/" + name + ".lua"), dir / (name + ".lua"));
  fs::copy(softcut::test::source("scenarios/meshes"), dir / "meshes", fs::copy_options::recursive);
  return dir / (name + ".lua");
}

int count_lines(const std::string& s, const std::string& prefix) {
  int n = 0;
  std::istringstream ss(s);
  for (std::string line; std::getline(ss, line);) n += line.rfind(prefix, 0) == 0;
  return n;
}

}  // namespace

TEST_SUITE("app/cmd_check") {
  TEST_CASE("the shipped scenarios pass against their references: one line each, then the tally") {
    int shipped = 0;  // every scenarios/*.lua
    for (const auto& e : fs::directory_iterator(fs::path(SOFTCUT_SOURCE_DIR) / "scenarios"))
      shipped += e.path().extension() == ".lua";
    REQUIRE(shipped >= 6);
    const std::string tally = std::to_string(shipped) + " passed, 0 failed\n";
    const auto r = run_cli("check scenarios");
    CHECK(r.status == 0);
    CHECK(count_lines(r.output, "PASS  ") == shipped);
    CHECK(contains(r.output, "\n" + tally));
    CHECK(r.output.size() > tally.size());
    CHECK(r.output.substr(r.output.size() - tally.size()) == tally);
  }

  TEST_CASE("a missing reference fails and says how to record one - --record then passes") {
    const fs::path s = copy_scenario("check_record", "upper_leg");
    const auto miss = run_cli("check --backend cpu " + s.string());
    CHECK(miss.status == 1);
    CHECK(contains(miss.output, "FAIL  " + s.string() + ": no reference log"));
    CHECK(contains(miss.output, "record one with `softcut check --record " + s.string() + "`"));
    CHECK(contains(miss.output, "0 passed, 1 failed"));
    const auto rec = run_cli("check --backend cpu --record " + s.string());
    CHECK(rec.status == 0);
    CHECK(fs::exists(softcut::app::reference_path(s)));
    // Recorded by this build: within the scenario's tolerance of the shipped reference.
    CHECK(softcut::app::compare_logs(softcut::app::reference_path(s), softcut::test::source("scenarios/upper_leg.ref.csv"), 1e-6).ok);
    CHECK(run_cli("check --backend cpu " + s.string()).status == 0);
  }

  TEST_CASE("a changed scenario or a stale reference fails naming the difference") {
    const fs::path s = copy_scenario("check_stale", "knee_ligament");
    fs::copy_file(softcut::test::source("scenarios/knee_ligament.ref.csv"), softcut::app::reference_path(s));
    const auto changed = run_cli("check --backend cpu " + s.string() + " --trust");
    CHECK(changed.status == 0);
    // A different force: same rows, different values.
    std::string text = slurp(s);
    text.replace(text.find("force = 5,"), 10, "force = 5.5,");
    std::ofstream(s) << text;
    const auto diff = run_cli("check --backend cpu " + s.string());
    CHECK(diff.status == 1);
    CHECK(contains(diff.output, "displacements differ from the reference by up to"));
    CHECK(contains(diff.output, " m (frame "));  // where the largest difference is
    CHECK(contains(diff.output, ", node "));
    CHECK(contains(diff.output, "if the change is intended, re-record one with `softcut check --record"));
    // A reference with other rows is stale.
    std::string ref = slurp(softcut::app::reference_path(s));
    ref.resize(ref.size() / 2);
    ref.resize(ref.rfind('\n') + 1);
    std::ofstream(softcut::app::reference_path(s)) << ref;
    const auto stale = run_cli("check --backend cpu " + s.string());
    CHECK(contains(stale.output, "stale reference"));
  }

  TEST_CASE("expectation failures and script errors are reported at the scenario's line") {
    const fs::path s = copy_scenario("check_expect", "liver_retraction");
    fs::copy_file(softcut::test::source("scenarios/liver_retraction.ref.csv"), softcut::app::reference_path(s));
    std::string text = slurp(s);
    std::ofstream(s) << text.replace(text.find("max = 1.02 * P.lift"), 19, "max = 0.9 * P.lift");
    // The default backend: the retraction's corotational lobe took the CG
    // backend's block-Jacobi Newton 142 s under ASan (CI); the kept factor's
    // Newton is 2.3x faster in Release (1.6 s against 3.7 s).
    const auto r = run_cli("check " + s.string());
    CHECK(r.status == 1);
    CHECK(contains(r.output, "liver_retraction.lua:59: expect 'edge lifted' failed: mean uz of 6 nodes at t = 2 s is "));
    const fs::path dir = s.parent_path();
    std::ofstream(dir / "broken.lua") << "local s = softcut.scenario{ duration = 1 }\ns:mesh{ generate = 'box' }\ns:material{ youngs = 1 }\n";
    const auto b = run_cli("check --backend cpu " + dir.string());
    CHECK(contains(b.output, "FAIL  " + (dir / "broken.lua").string() + ": " + (dir / "broken.lua").string() +
                                 ":3: material: unknown field 'youngs' (did you mean 'young'?)"));
    CHECK(contains(b.output, "0 passed, 2 failed"));
  }

  TEST_CASE("--max-tets bounds the mesh a scenario may generate, naming the line and the flag") {
    const std::string s = softcut::test::source("scenarios/through_cut.lua");  // a 960-tet box
    const auto r = run_cli("check --backend cpu --max-tets 959 " + s);
    CHECK(r.status == 1);
    CHECK(contains(r.output, "through_cut.lua:17: mesh generator 'box': this resolution gives 960 tetrahedra, over "
                             "this run's limit of 959; use a coarser one (softcut run/check --max-tets N raises the "
                             "limit, --trust lifts it)"));
    CHECK(run_cli("check --backend cpu --max-tets 960 " + s).status == 0);
    CHECK(contains(run_cli("check --max-tets lots " + s).output, "--max-tets lots: expected a whole number"));
  }

  // Issue #18: a folder with a passing scenario, one whose expectation fails,
  // one with a corrupt reference and a helper module.
  TEST_CASE("a corrupt reference fails only its scenario, the others run, modules are required and skipped, no temporary folder is left") {
    const fs::path dir = softcut::test::scratch_dir("check_corrupt");
    write_bar(dir / "a.lua", "bar_a");
    write_bar(dir / "b.lua", "bar_b", "false");
    write_bar(dir / "c.lua", "bar_c");
    std::ofstream(dir / "common.lua") << "local M = {}\nfunction M.twice(x) return 2 * x end\nreturn M\n";
    const std::string a = slurp(dir / "a.lua");  // a uses the module beside it
    std::ofstream(dir / "a.lua") << "assert(require('common').twice(2) == 4)\n" << a;
    REQUIRE(run_cli("check --record " + dir.string()).status == 1);  // b fails, a and c recorded
    REQUIRE(fs::exists(dir / "c.ref.csv"));
    std::string ref = slurp(dir / "c.ref.csv");
    std::ofstream(dir / "c.ref.csv") << ref.substr(0, ref.find('\n') + 1) << "1,0.1,oops\n";
    const fs::path tmp = dir / "tmp";
    fs::create_directories(tmp);
    const auto r = run_cli("check " + dir.string(), SOFTCUT_SOURCE_DIR, "TMPDIR='" + tmp.string() + "'");
    CHECK(r.status == 1);
    CHECK(contains(r.output, "PASS  " + (dir / "a.lua").string()));
    CHECK(contains(r.output, "FAIL  " + (dir / "b.lua").string() + ": " + (dir / "b.lua").string() +
                                 ":8: expect 'holds' failed: f = 0.01"));
    CHECK(contains(r.output, "FAIL  " + (dir / "c.lua").string() + ": " + (dir / "c.ref.csv").string() +
                                 ":2: expected frame,time,node,ux,uy,uz"));
    CHECK(contains(r.output, "SKIP  " + (dir / "common.lua").string() + ": makes no scenario (a helper module?)"));
    CHECK(contains(r.output, "1 passed, 2 failed, 1 skipped\n"));
    CHECK(fs::is_empty(tmp));  // softcut-check-PID removed
  }

  TEST_CASE("-j 2 gives the same verdicts in the same order as -j 1") {
    const fs::path dir = softcut::test::scratch_dir("check_jobs");
    for (int k = 0; k < 6; ++k)
      write_bar(dir / ("s" + std::to_string(k) + ".lua"), "bar_" + std::to_string(k), k % 3 == 1 ? "false" : "true");
    run_cli("check --record " + dir.string());
    const auto one = run_cli("check -j 1 " + dir.string()), two = run_cli("check -j 2 " + dir.string());
    CHECK(one.status == 1);
    CHECK(two.status == 1);
    CHECK(verdicts(one.output).size() == 6);
    CHECK(verdicts(one.output) == verdicts(two.output));
    CHECK(contains(two.output, "4 passed, 2 failed\n"));
    CHECK(run_cli("check -j 0 " + dir.string()).status == 2);
  }

  TEST_CASE("--only and --exclude pick scenarios by name or file glob, --set reaches every scenario, --timeout fails a long one") {
    const fs::path dir = softcut::test::scratch_dir("check_filter");
    write_bar(dir / "first.lua", "alpha", "P.f < 0.05");
    write_bar(dir / "second.lua", "beta", "P.f < 0.05");
    run_cli("check --record " + dir.string());
    CHECK(verdicts(run_cli("check --only alpha " + dir.string()).output) ==
          std::vector<std::string>{"PASS  " + (dir / "first.lua").string()});
    CHECK(verdicts(run_cli("check --only 'sec*' " + dir.string()).output) ==
          std::vector<std::string>{"PASS  " + (dir / "second.lua").string()});
    CHECK(verdicts(run_cli("check --exclude 'a?pha' " + dir.string()).output) ==
          std::vector<std::string>{"PASS  " + (dir / "second.lua").string()});
    const auto none = run_cli("check --only nothing " + dir.string());
    CHECK(none.status == 2);
    CHECK(contains(none.output, "no scenario left after --only/--exclude"));
    const auto set = run_cli("check --set f=0.1 " + dir.string());
    CHECK(set.status == 1);
    CHECK(contains(set.output, "expect 'holds' failed: f = 0.1"));
    CHECK(contains(set.output, "0 passed, 2 failed"));
    CHECK(run_cli("check --set f " + dir.string()).status == 2);
    std::string slow = slurp(dir / "first.lua");
    std::ofstream(dir / "slow.lua") << slow.replace(slow.find("duration = 0.2, fps = 10"), 24,
                                                    "duration = 1000, fps = 100") .replace(slow.find("'alpha'"), 7, "'slow'");
    const auto late = run_cli("check --timeout 0.5 --only slow " + dir.string());
    CHECK(late.status == 1);
    CHECK(contains(late.output, "FAIL  " + (dir / "slow.lua").string()));
    CHECK(contains(late.output, "wall-clock limit"));
  }

  TEST_CASE("two scenarios with one name are a usage error naming both files") {
    const fs::path dir = softcut::test::scratch_dir("check_dup");
    write_bar(dir / "one.lua", "same");
    write_bar(dir / "two.lua", "same");
    const auto r = run_cli("check " + dir.string());
    CHECK(r.status == 2);
    CHECK(contains(r.output, "two scenarios are named 'same': " + (dir / "one.lua").string() + " and " +
                                 (dir / "two.lua").string()));
    CHECK(run_cli("check --frobnicate " + dir.string()).status == 2);
  }

  // Issue #40 item 5: a copied reference was called stale, and --record overwrote it.
  TEST_CASE("a reference says who made it: another scenario's is named, --record keeps it without --force, old ones read") {
    const fs::path dir = softcut::test::scratch_dir("check_ref_header");
    write_bar(dir / "a.lua", "bar_a");
    write_bar(dir / "b.lua", "bar_b");
    REQUIRE(run_cli("check --record " + (dir / "a.lua").string()).status == 0);
    const std::string a_ref = slurp(dir / "a.ref.csv");
    CHECK(a_ref.rfind("# softcut-reference: {\"scenario\":\"bar_a\",\"mesh\":\"fnv1a64:", 0) == 0);
    CHECK(contains(a_ref, "\"params\":{\"f\":\"0.01\"}"));
    fs::copy_file(dir / "a.ref.csv", dir / "b.ref.csv");  // the same motion: it compared equal before
    const auto foreign = run_cli("check " + (dir / "b.lua").string());
    CHECK(foreign.status == 1);
    CHECK(contains(foreign.output, "this reference was made by scenario 'bar_a', not 'bar_b' (" +
                                       (dir / "b.ref.csv").string() + ")"));
    CHECK(!contains(foreign.output, "stale"));
    const auto keep = run_cli("check --record " + (dir / "b.lua").string());
    CHECK(keep.status == 1);
    CHECK(contains(keep.output, (dir / "b.ref.csv").string() + " was recorded by scenario 'bar_a', not 'bar_b'; "
                                "--record would overwrite another scenario's reference: move it away, or give --force"));
    CHECK(slurp(dir / "b.ref.csv") == a_ref);
    CHECK(run_cli("check --record --force " + (dir / "b.lua").string()).status == 0);
    CHECK(slurp(dir / "b.ref.csv").rfind("# softcut-reference: {\"scenario\":\"bar_b\"", 0) == 0);
    CHECK(run_cli("check " + (dir / "b.lua").string()).status == 0);
    // A reference recorded before headers existed still reads (and --record may replace it).
    std::ofstream(dir / "a.ref.csv", std::ios::trunc) << a_ref.substr(a_ref.find('\n') + 1);
    CHECK(run_cli("check " + (dir / "a.lua").string()).status == 0);
    // Other parameters: said when the log differs.
    std::ofstream(dir / "a.ref.csv", std::ios::trunc) << a_ref;
    const auto other = run_cli("check --set f=0.02 " + (dir / "a.lua").string());
    CHECK(other.status == 1);
    CHECK(contains(other.output, "displacements differ from the reference"));
    CHECK(contains(other.output, "(the reference was recorded with f=0.01, this run has f=0.02)"));
  }

  // Issue #40 item 6: the comparison was skipped (comparison: null) when an expectation failed.
  TEST_CASE("a failed expectation and a differing log are both reported") {
    const fs::path dir = softcut::test::scratch_dir("check_both");
    write_bar(dir / "c.lua", "bar_c", "P.f < 0.05");
    REQUIRE(run_cli("check --record " + (dir / "c.lua").string()).status == 0);
    const fs::path json = dir / "r.json";
    const auto r = run_cli("check --set f=0.1 --json " + json.string() + " " + (dir / "c.lua").string());
    CHECK(r.status == 1);
    CHECK(contains(r.output, "FAIL  " + (dir / "c.lua").string() + ": " + (dir / "c.lua").string() +
                                 ":8: expect 'holds' failed: f = 0.1"));
    CHECK(contains(r.output, "      displacements differ from the reference by up to"));
    const auto j = softcut::test::read_json(json);
    CHECK(j["scenarios"][0]["failures"].size() == 2);
    REQUIRE(j["scenarios"][0].contains("comparison"));
    CHECK(j["scenarios"][0]["comparison"]["max_diff_m"].get<double>() > 0);
    // A failing scenario records nothing.
    const std::string before = slurp(softcut::app::reference_path(dir / "c.lua"));
    CHECK(run_cli("check --record --set f=0.1 " + (dir / "c.lua").string()).status == 1);
    CHECK(slurp(softcut::app::reference_path(dir / "c.lua")) == before);
  }

  TEST_CASE("a scenario's warnings show under its line, --warnings-as-errors fails it, records nothing, the shipped ones pass") {
    const fs::path dir = softcut::test::scratch_dir("check_warnings");
    // Stiff (5 MPa): the 5 kPa bar turns its tip 43 deg, which the linear
    // model's validity warning would rightly add (sim/validity).
    const std::string stiff = "s:material{ young = 5e6, poisson = 0.4 }\n";
    write_bar(dir / "quiet.lua", "quiet", "true", stiff);
    // A probe far above the bar: it never touches.
    write_bar(dir / "miss.lua", "miss", "true",
              stiff + "s:probe{ name = 'tip', path = softcut.path.fixed{ 0.05, 0.01, 0.05 }, radius = 0.002, force = 0.1 }\n");
    REQUIRE(run_cli("check --record " + dir.string()).status == 0);
    const std::string warning = (dir / "miss.lua").string() + ":10: probe 'tip' never touched the tissue (closest 28 "
                                "mm at t = 0 s); move its path onto the surface or give it a larger radius "
                                "[tool_never_touched]";
    const auto plain = run_cli("check " + dir.string());
    INFO(plain.output);
    CHECK(plain.status == 0);
    CHECK(contains(plain.output, "PASS  " + (dir / "miss.lua").string()));
    CHECK(contains(plain.output, ")\n      warning: " + warning + "\nPASS  " + (dir / "quiet.lua").string()));
    const std::string before = slurp(softcut::app::reference_path(dir / "miss.lua"));
    const fs::path json = dir / "r.json";
    const auto strict = run_cli("check --warnings-as-errors --record --json " + json.string() + " " + dir.string());
    INFO(strict.output);
    CHECK(strict.status == 1);
    CHECK(contains(strict.output, "FAIL  " + (dir / "miss.lua").string() +
                                      ": 1 warning with --warnings-as-errors: " + warning + "\n"));
    CHECK(contains(strict.output, "PASS  " + (dir / "quiet.lua").string()));
    CHECK(slurp(softcut::app::reference_path(dir / "miss.lua")) == before);
    const auto j = softcut::test::read_json(json);
    CHECK(j["scenarios"][0]["warnings"] == nlohmann::ordered_json::array({warning}));
    CHECK(j["scenarios"][0]["warnings_total"] == 1);
    CHECK(j["scenarios"][1]["warnings"].empty());
    // No false alarm: the shipped scenarios' tools all act, their materials
    // and sizes are plausible, and those that deform a lot carry a nonlinear
    // law in an operational region drawn round what turns (issue #43 item 8).
    // Only upper_leg, the paper's experiment with its tools on the condensed
    // region, warns that the condensed region turns past 10 deg.
    const fs::path shipped_json = dir / "shipped.json";
    const auto shipped = run_cli("check " + softcut::test::source("scenarios") + " --json " + shipped_json.string());
    INFO(shipped.output);
    CHECK(shipped.status == 0);
    std::map<std::string, std::set<std::string>> codes;
    const auto report = softcut::test::read_json(shipped_json);
    for (const auto& sc : report["scenarios"])
      for (const auto& w : sc["warnings"])
        codes[sc["name"].get<std::string>()].insert(std::string(softcut::warning_code(w.get<std::string>())));
    for (const auto& entry : codes)
      for (const auto& code : entry.second) {
        CAPTURE(entry.first);
        CHECK((code == "linear_large_rotation" || code == "linear_large_strain" || code == "condensed_rotation"));
      }
    CHECK(report["scenarios"].size() == 8);
    for (const auto& sc : report["scenarios"]) {
      const std::string name = sc["name"].get<std::string>();
      CAPTURE(name);
      if (name == "upper_leg")
        CHECK(codes[name] == std::set<std::string>{"condensed_rotation"});
      else
        CHECK(codes[name].empty());
    }
    // With the paper's linear law (the scenarios' `model` parameter) the
    // retraction and the dragged lip turn linear tets by 20 and 54 deg, as
    // issue #43 measured from outside.
    for (const char* name : {"liver_retraction", "incision_drag_poke"}) {
      CAPTURE(name);
      const auto linear = run_cli(std::string("run ") + softcut::test::source("scenarios/") + name +
                                  ".lua --set model=linear --no-render --out " + (dir / name).string());
      CHECK(linear.status == 0);
      CHECK(contains(linear.output, "[linear_large_rotation]"));
    }
  }

  TEST_CASE("--junit writes JUnit XML that validates against the schema CI systems read, --json the same facts") {
    const fs::path dir = softcut::test::scratch_dir("check_reports");
    write_bar(dir / "good.lua", "good");
    write_bar(dir / "bad.lua", "bad", "false");
    std::ofstream(dir / "helper.lua") << "return { x = 1 }\n";
    run_cli("check --record " + dir.string());
    const fs::path xml = dir / "out" / "report.xml", json = dir / "out" / "report.json";
    fs::create_directories(xml.parent_path());
    const auto r = run_cli("check --junit " + xml.string() + " --json " + json.string() + " " + dir.string());
    CHECK(r.status == 1);
    const auto lint = softcut::test::run_cli_raw("xmllint --noout --schema '" +
                                                 softcut::test::source("tests/data/junit.xsd") + "' '" +
                                                 xml.string() + "'");
    INFO(lint.output);
    CHECK(lint.status == 0);
    const std::string x = slurp(xml);
    CHECK(contains(x, "tests=\"3\" failures=\"1\""));
    CHECK(contains(x, "skipped=\"1\""));
    CHECK(contains(x, "<testcase name=\"bad\" classname=\"" + (dir / "bad.lua").string() + "\""));
    CHECK(contains(x, "<failure message=\"" + (dir / "bad.lua").string() + ":8: expect 'holds' failed"));
    const nlohmann::ordered_json j = softcut::test::read_json(json);
    CHECK(j["passed"] == 1);
    CHECK(j["failed"] == 1);
    CHECK(j["skipped"] == 1);
    REQUIRE(j["scenarios"].size() == 3);
    for (const auto& s : j["scenarios"]) {
      if (s["name"] == "good") {
        CHECK(s["status"] == "pass");
        CHECK(s["expectations"].size() == 1);
        CHECK(s["expectations"][0]["ok"] == true);
        CHECK(s["comparison"]["max_diff_m"].get<double>() <= s["comparison"]["tolerance"].get<double>() *
                                                                  s["comparison"]["scale_m"].get<double>());
      } else if (s["name"] == "bad") {
        CHECK(s["status"] == "fail");
        CHECK(s["expectations"][0]["ok"] == false);
        CHECK(s["expectations"][0]["message"] == "f = 0.01");
      } else {
        CHECK(s["status"] == "skipped");
      }
    }
  }
}
