// engine/cli/cmd_check.cpp (+ reference_log.cpp) through the real executable.
#include <doctest/doctest.h>

#include <fstream>

#include "cli/reference_log.hpp"
#include "cli_test_support.hpp"

namespace fs = std::filesystem;
using softcut::test::contains;
using softcut::test::run_cli;
using softcut::test::slurp;

namespace {

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

TEST_SUITE("cli/cmd_check") {
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
    CHECK(fs::exists(softcut::cli::reference_path(s)));
    // Recorded by this build: within the scenario's tolerance of the shipped reference.
    CHECK(softcut::cli::compare_logs(softcut::cli::reference_path(s), softcut::test::source("scenarios/upper_leg.ref.csv"), 1e-6).ok);
    CHECK(run_cli("check --backend cpu " + s.string()).status == 0);
  }

  TEST_CASE("a changed scenario or a stale reference fails naming the difference") {
    const fs::path s = copy_scenario("check_stale", "knee_ligament");
    fs::copy_file(softcut::test::source("scenarios/knee_ligament.ref.csv"), softcut::cli::reference_path(s));
    const auto changed = run_cli("check --backend cpu " + s.string() + " --trust");
    CHECK(changed.status == 0);
    // A different force: same rows, different values.
    std::string text = slurp(s);
    text.replace(text.find("force = 5,"), 10, "force = 5.5,");
    std::ofstream(s) << text;
    const auto diff = run_cli("check --backend cpu " + s.string());
    CHECK(diff.status == 1);
    CHECK(contains(diff.output, "displacements differ from the reference by up to"));
    CHECK(contains(diff.output, "if the change is intended, re-record one with `softcut check --record"));
    // A reference with other rows is stale.
    std::string ref = slurp(softcut::cli::reference_path(s));
    ref.resize(ref.size() / 2);
    ref.resize(ref.rfind('\n') + 1);
    std::ofstream(softcut::cli::reference_path(s)) << ref;
    const auto stale = run_cli("check --backend cpu " + s.string());
    CHECK(contains(stale.output, "stale reference"));
  }

  TEST_CASE("expectation failures and script errors are reported at the scenario's line") {
    const fs::path s = copy_scenario("check_expect", "liver_retraction");
    fs::copy_file(softcut::test::source("scenarios/liver_retraction.ref.csv"), softcut::cli::reference_path(s));
    std::string text = slurp(s);
    std::ofstream(s) << text.replace(text.find("max = 1.02 * P.lift"), 19, "max = 0.9 * P.lift");
    const auto r = run_cli("check --backend cpu " + s.string());
    CHECK(r.status == 1);
    CHECK(contains(r.output, "liver_retraction.lua:46: expect 'edge lifted' failed: mean uz of 4 nodes at t = 2 s is "));
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
    CHECK(contains(r.output, "through_cut.lua:16: mesh generator 'box': this resolution gives 960 tetrahedra, over "
                             "this run's limit of 959; use a coarser one (softcut run/check --max-tets N raises the "
                             "limit, --trust lifts it)"));
    CHECK(run_cli("check --backend cpu --max-tets 960 " + s).status == 0);
    CHECK(contains(run_cli("check --max-tets lots " + s).output, "--max-tets lots: expected a whole number"));
  }
}
