// softcut sweep / sweep merge through the CLI (issue #18 item 5).
#include <doctest/doctest.h>

#include <fstream>

#include "cli_test_support.hpp"

namespace fs = std::filesystem;
using softcut::test::contains;
using softcut::test::run_cli;
using softcut::test::slurp;

namespace {

// A small cantilever with two parameters and one bounds expectation (its
// value goes into the table) that fails for the largest force.
fs::path write_scenario(const fs::path& dir) {
  std::ofstream(dir / "bar.lua")
      << "local P = softcut.params{ f = 0.01, young = 5e3 }\n"
         "local s = softcut.scenario{ name = 'bar', duration = 0.2, fps = 10 }\n"
         "s:mesh{ generate = 'box', options = { max = { 0.1, 0.02, 0.02 }, nx = 5, ny = 2, nz = 2 } }\n"
         "s:material{ young = P.young, poisson = 0.4 }\n"
         "local tip = softcut.select.box{ min = { 0.1, -1, -1 }, max = { 1, 1, 1 } }\n"
         "s:fix{ nodes = softcut.select.box{ min = { -1, -1, -1 }, max = { 0, 1, 1 } } }\n"
         "s:load{ name = 'tip', nodes = tip, force = { 0, 0, -P.f } }\n"
         "s:expect{ name = 'sag', at = 0.2, nodes = tip, component = 'z', min = -1 }\n"
         "return s\n";
  return dir / "bar.lua";
}

// A file the sweep must not truncate, hard-linked as run_0001's run.log.
void put_hard_link(const fs::path& dir) {
  std::ofstream(dir / "precious.txt") << "keep";
  fs::create_hard_link(dir / "precious.txt", dir / "s" / "run_0001" / "run.log");
}

const char* kGrid = "--grid f=0.001,0.01,0.1,1 --grid young=5e3,1e4";  // 8 runs; f = 1 N at 5 kPa sags 1.6 m (linear), past 1 m

}  // namespace

// A bar pulled up by a spring grasper 'jaw' of stiffness parameter k, with
// `extra` script lines before its return.
static void write_pull(const fs::path& file, const std::string& extra) {
  std::ofstream(file) << "local P = softcut.params{ k = 100 }\n"
                      "local s = softcut.scenario{ name = 'pull', duration = 0.2, fps = 10 }\n"
                      "s:mesh{ generate = 'box', options = { max = { 0.1, 0.02, 0.02 }, nx = 10, ny = 4, nz = 4 } }\n"
                      "s:material{ young = 5e3, poisson = 0.4 }\n"
                      "s:fix{ nodes = softcut.select.box{ min = { -1, -1, -1 }, max = { 0, 1, 1 } } }\n"
                      "s:grasper{ name = 'jaw', radius = 0.006, stiffness = P.k, path = softcut.path.polyline{ times = { 0, 0.2 },\n"
                      "           points = { { 0.08, 0.01, 0.021 }, { 0.08, 0.01, 0.028 } } } }\n"
                      << extra << "return s\n";
}

TEST_SUITE("app/cmd_sweep") {
  TEST_CASE("8 runs in 3 shards merge to the same table as one local run - a missing shard fails the merge") {
    const fs::path dir = softcut::test::scratch_dir("sweep_shards");
    const fs::path scen = write_scenario(dir);
    const std::string env = "SOFTCUT_THREADS=1";
    const auto local = run_cli("sweep " + scen.string() + " " + kGrid + " -j 2 --out " + (dir / "local").string(),
                               dir, env);
    CHECK(local.status == 1);  // one run fails its expectation
    CHECK(contains(local.output, "8 runs; 8 here, 2 at once"));
    CHECK(contains(local.output, "PASS  run_0000  f=0.001 young=5e3"));
    CHECK(contains(local.output, "FAIL  run_0006  f=1 young=5e3: " + scen.string() + ":8: expect 'sag' failed"));
    CHECK(contains(local.output, "7 passed, 1 failed"));
    const auto merged_local = run_cli("sweep merge " + (dir / "local").string(), dir);
    CHECK(merged_local.status == 1);
    CHECK(contains(merged_local.output, "merged 8 runs: 7 passed, 1 failed"));
    const std::string table = slurp(dir / "local" / "sweep.csv");
    CHECK(table.rfind("id,f,young,pass,exit_reason,frames,last_time_s,cut_events,detached_pieces,expect.sag\n"
                      "run_0000,0.001,5e3,true,completed,3,0.2,0,0,-", 0) == 0);
    CHECK(contains(table, "\nrun_0006,1,5e3,false,completed,3,0.2,0,0,-"));

    // Shards 0 and 2 of 3 only: the merge names the missing runs (1, 4, 7).
    const fs::path sharded = dir / "sharded";
    for (const char* s : {"0/3", "2/3"}) {
      const auto r = run_cli("sweep " + scen.string() + " " + kGrid + " --shard " + s + " --out " + sharded.string(),
                             dir, env);
      CHECK(contains(r.output, std::string("(--shard ") + s + ")"));
    }
    const auto partial = run_cli("sweep merge " + sharded.string(), dir);
    CHECK(partial.status == 1);
    CHECK(contains(partial.output, "3 of 8 runs have no summary.json: run_0001, run_0004, run_0007"));
    CHECK(!fs::exists(sharded / "sweep.csv"));
    // Shard 1 through Slurm's variables; then the tables are the same bytes.
    const auto slurm = run_cli("sweep " + scen.string() + " " + kGrid + " --out " + sharded.string(), dir,
                               env + " SLURM_ARRAY_TASK_ID=11 SLURM_ARRAY_TASK_MIN=10 SLURM_ARRAY_TASK_COUNT=3");
    CHECK(contains(slurm.output, "3 here"));
    CHECK(contains(slurm.output, "PASS  run_0001"));
    CHECK(run_cli("sweep merge " + sharded.string(), dir).status == 1);
    CHECK(slurp(sharded / "sweep.csv") == table);
    CHECK(slurp(sharded / "sweep.json") == slurp(dir / "local" / "sweep.json"));
    // Each run's summary records the command that reruns it alone.
    const std::vector<std::string> cmd = softcut::test::read_json(sharded / "run_0003" / "summary.json")["command_line"];
    REQUIRE(cmd.size() >= 4);
    CHECK(std::vector<std::string>(cmd.end() - 4, cmd.end()) ==
          std::vector<std::string>{"--set", "f=0.01", "--set", "young=1e4"});
  }

  TEST_CASE("a folder holding another sweep, unknown parameters and bad options are refused before any run") {
    const fs::path dir = softcut::test::scratch_dir("sweep_refused");
    const fs::path scen = write_scenario(dir);
    const std::string out = " --out " + (dir / "s").string();
    REQUIRE(run_cli("sweep " + scen.string() + " --grid f=0.01,0.02" + out, dir).status == 0);
    const auto other = run_cli("sweep " + scen.string() + " --grid f=0.01,0.03" + out, dir);
    CHECK(other.status == 1);
    CHECK(contains(other.output, "holds another sweep"));
    const auto unknown = run_cli("sweep " + scen.string() + " --grid stiffness=1,2 --out " + (dir / "u").string(), dir);
    CHECK(unknown.status != 0);
    CHECK(contains(unknown.output, "stiffness"));
    CHECK(!fs::exists(dir / "u"));
    CHECK(run_cli("sweep " + scen.string() + " --grid f=1 --table t.csv", dir).status == 2);
    CHECK(run_cli("sweep " + scen.string() + " --grid f=1 --frames x", dir).status == 2);
    CHECK(run_cli("sweep " + scen.string() + " --grid f=1 --shard 3/3", dir).status == 2);
    CHECK(run_cli("sweep " + scen.string() + " --grid f=1 --set f=2", dir).status == 2);
    CHECK(run_cli("sweep " + scen.string() + " --grid f=1 --bogus", dir).status == 2);
    CHECK(run_cli("sweep merge " + (dir / "nowhere").string(), dir).status == 1);
    const auto help = run_cli("sweep --help", dir);
    CHECK(help.status == 0);
    CHECK(contains(help.output, "SLURM_ARRAY_TASK_ID"));
  }

  TEST_CASE("a run that fails before its outputs start is a failed row, never an earlier run's pass") {
    const fs::path dir = softcut::test::scratch_dir("sweep_stale");
    const fs::path scen = write_scenario(dir);
    const std::string sweep = "sweep " + scen.string() + " --grid f=0.01,0.02 --out s";
    REQUIRE(run_cli(sweep, dir).status == 0);
    REQUIRE(run_cli("sweep merge s", dir).status == 0);
    // The scenario now refuses f = 0.02 in its main chunk: no outputs, no summary of its own.
    const std::string text = slurp(scen);
    std::ofstream(scen) << text.substr(0, text.find("local s ="))
                        << "if P.f == 0.02 then error('f = 0.02 is refused') end\n" << text.substr(text.find("local s ="));
    fs::remove(dir / "s" / "run_0001" / "run.log");
    put_hard_link(dir);
    const auto again = run_cli(sweep, dir);
    CHECK(again.status == 1);
    CHECK(contains(again.output, "FAIL  run_0001  f=0.02: " + scen.string() + ":2: f = 0.02 is refused"));
    CHECK(slurp(dir / "precious.txt") == "keep");  // run.log was a hard link to it: unlinked, not truncated
    const auto merged = run_cli("sweep merge s", dir);
    CHECK(merged.status == 1);
    CHECK(contains(merged.output, "merged 2 runs: 1 passed, 1 failed"));
    CHECK(contains(slurp(dir / "s" / "sweep.csv"), "\nrun_0001,0.02,false,error,0,,"));
  }

  TEST_CASE("tables: a byte order mark is skipped, a NUL refused, keys named like columns get param. columns") {
    const fs::path dir = softcut::test::scratch_dir("sweep_bom");
    const fs::path scen = dir / "cols.lua";
    const std::string bar = slurp(write_scenario(dir));
    std::ofstream(scen) << "local P = softcut.params{ frames = 1, f = 0.01, young = 5e3 }" << bar.substr(bar.find('\n'));
    std::ofstream(dir / "p.csv") << "\xEF\xBB\xBF" << "frames,f\n1,0.01\n";
    CHECK(run_cli("sweep " + scen.string() + " --table p.csv --out t", dir).status == 0);
    CHECK(run_cli("sweep merge t", dir).status == 0);
    CHECK(slurp(dir / "t" / "sweep.csv").rfind("id,param.frames,f,pass,exit_reason,frames,", 0) == 0);
    std::ofstream(dir / "nul.csv") << "f\n0.01\n0.0" << '\0' << "2\n";
    const auto nul = run_cli("sweep " + scen.string() + " --table nul.csv --out n", dir);
    CHECK(nul.status == 1);
    CHECK(contains(nul.output, "nul.csv:3: a NUL byte"));
  }

  TEST_CASE("--table runs one row each, --dry-run lists this shard's runs and runs nothing") {
    const fs::path dir = softcut::test::scratch_dir("sweep_table_cli");
    const fs::path scen = write_scenario(dir);
    std::ofstream(dir / "p.csv") << "young,f\n5e3,0.01\n1e4,0.02\n2e4,0.04\n";
    const auto dry = run_cli("sweep " + scen.string() + " --table p.csv --dry-run --shard 1/2 --out d", dir);
    CHECK(dry.status == 0);
    CHECK(contains(dry.output, "3 runs; --shard 1/2 runs 1 of them"));
    CHECK(contains(dry.output, "run_0001  young=1e4 f=0.02"));
    CHECK(!fs::exists(dir / "d"));
    CHECK(run_cli("sweep " + scen.string() + " --table p.csv -j 1 --frames 2 --out t", dir).status == 0);
    CHECK(run_cli("sweep merge t", dir).status == 0);
    const std::string csv = slurp(dir / "t" / "sweep.csv");
    CHECK(contains(csv, "id,young,f,pass,"));
    CHECK(contains(csv, "\nrun_0002,2e4,0.04,true,frame_limit,2,"));
  }

  TEST_CASE("each tool's peak and mean force and engaged frames become columns of sweep.csv") {
    const fs::path dir = softcut::test::scratch_dir("sweep_tools");
    write_pull(dir / "pull.lua", "");
    CHECK(run_cli("sweep pull.lua --grid k=100,400 -j 1 --out t", dir).status == 0);
    CHECK(run_cli("sweep merge t", dir).status == 0);
    const std::string csv = slurp(dir / "t" / "sweep.csv");
    CHECK(contains(csv, ",tool.jaw.peak_force_n,tool.jaw.mean_force_n,tool.jaw.frames_engaged\n"));
    for (const char* run : {"run_0000", "run_0001"}) {
      const auto summary = softcut::test::read_json(dir / "t" / run / "summary.json");
      const auto& jaw = summary.at("tools").at(0);
      REQUIRE(jaw.at("peak_force_n").get<double>() > 0);
      CHECK(contains(csv, "," + jaw.at("peak_force_n").dump() + "," + jaw.at("mean_force_n").dump() + "," +
                              jaw.at("frames_engaged").dump() + "\n"));
    }
    const auto sweep = softcut::test::read_json(dir / "t" / "sweep.json");
    CHECK(sweep.at("rows").at(1).at("tools").at(0).at("name") == "jaw");
  }

  TEST_CASE("numbers a scenario records (Frame:record) land in summary.json and as metric columns of sweep.csv") {
    // The jaw's force magnitude recorded every frame: its max must be the
    // tool's own peak force (tools.csv's statistics), its last the last frame's.
    const fs::path dir = softcut::test::scratch_dir("sweep_metrics");
    write_pull(dir / "pull.lua",
               "s:on_frame(function(f)\n"
               "  f:record('jaw_force', softcut.vec.length(f:tool('jaw').force))\n"
               "  if f.frame == 2 then f:record('lift.mm', 1000 * f:mean_displacement(softcut.select.surface())[3]) end\n"
               "end)\n");
    CHECK(run_cli("sweep pull.lua --grid k=100,400 -j 1 --out t", dir).status == 0);
    CHECK(run_cli("sweep merge t", dir).status == 0);
    const std::string csv = slurp(dir / "t" / "sweep.csv");
    CHECK(contains(csv, ",tool.jaw.frames_engaged,metric.jaw_force,metric.lift.mm\n"));
    for (const char* run : {"run_0000", "run_0001"}) {
      CAPTURE(run);
      const auto summary = softcut::test::read_json(dir / "t" / run / "summary.json");
      const auto& metrics = summary.at("metrics");
      REQUIRE(metrics.size() == 2);
      const auto& force = metrics.at(0);
      CHECK(force.at("name") == "jaw_force");
      CHECK(force.at("samples") == 3);
      CHECK(force.at("frame") == 2);
      CHECK(force.at("max").get<double>() == doctest::Approx(summary.at("tools").at(0).at("peak_force_n").get<double>()));
      CHECK(force.at("min").get<double>() <= force.at("mean").get<double>());
      CHECK(metrics.at(1).at("samples") == 1);
      CHECK(metrics.at(1).at("value").get<double>() > 0);
      CHECK(contains(csv, "," + force.at("value").dump() + "," + metrics.at(1).at("value").dump() + "\n"));
    }
    const auto sweep = softcut::test::read_json(dir / "t" / "sweep.json");
    CHECK(sweep.at("rows").at(1).at("metrics").at(0).at("name") == "jaw_force");
    // A name that cannot be a column is the script's error, at its line.
    std::ofstream(dir / "bad.lua") << "local s = softcut.scenario{ duration = 0.1, fps = 10 }\n"
                                      "s:mesh{ generate = 'box' }\n"
                                      "s:fix{ nodes = softcut.select.box{ min = { -1, -1, -1 }, max = { 0, 1, 1 } } }\n"
                                      "s:on_frame(function(f) f:record('jaw force', 1) end)\n"
                                      "return s\n";
    const auto bad = run_cli("run bad.lua --no-render --out b", dir);
    CHECK(bad.status != 0);
    CHECK(contains(bad.output, "bad.lua:4:"));
    CHECK(contains(bad.output, "metric name 'jaw force' is not 1 to 64 letters"));
  }
}
