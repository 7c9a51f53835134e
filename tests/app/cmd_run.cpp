// app/cmd_run.cpp through the real executable (SOFTCUT_BIN).
#include <doctest/doctest.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <fstream>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include "core/warning.hpp"
#include "cli_test_support.hpp"

namespace fs = std::filesystem;
using softcut::test::contains;
using softcut::test::run_cli;
using softcut::test::slurp;

TEST_SUITE("app/cmd_run") {
  TEST_CASE("runs the flagship scenario into --out, quietly") {
    const fs::path out = softcut::test::scratch_dir("cli_run") / "leg";
    const auto r = run_cli("run " + softcut::test::source("scenarios/upper_leg.lua") + " --out " + out.string() + " --quiet");
    CHECK(r.status == 0);
    CHECK(r.output == "");  // --quiet: nothing
    CHECK(contains(slurp(out / "summary.json"), "\"exit_reason\": \"completed\""));
    CHECK(slurp(out / "displacements.csv").rfind("frame,time,node,ux,uy,uz\n", 0) == 0);
  }

  TEST_CASE("a rendering scenario writes frames and a contact sheet, --no-render writes neither") {
    const fs::path dir = softcut::test::scratch_dir("cli_run_render");
    const std::string flagship = softcut::test::source("scenarios/incision_drag_poke.lua");
    const auto r = run_cli("run " + flagship + " --out " + (dir / "on").string() + " --quiet --frames 5");
    CHECK(r.status == 0);
    CHECK(fs::exists(dir / "on" / "frames" / "frame_000000.png"));
    CHECK(fs::exists(dir / "on" / "frames" / "frame_000004.png"));  // every 2nd frame: 0, 2, 4
    CHECK_FALSE(fs::exists(dir / "on" / "frames" / "frame_000001.png"));
    CHECK(fs::exists(dir / "on" / "contact_sheet.png"));
    CHECK(contains(slurp(dir / "on" / "summary.json"), "\"frames_rendered\": 3"));
    const auto off = run_cli("run " + flagship + " --out " + (dir / "off").string() + " --quiet --frames 5 --no-render");
    CHECK(off.status == 0);
    CHECK(fs::exists(dir / "off" / "summary.json"));
    CHECK_FALSE(fs::exists(dir / "off" / "frames"));
    CHECK_FALSE(fs::exists(dir / "off" / "contact_sheet.png"));
    CHECK(contains(slurp(dir / "off" / "summary.json"), "\"frames_rendered\": 0"));
  }

  TEST_CASE("a second run loads the precompute from the cache and writes the same displacements bit for bit") {
    const fs::path dir = softcut::test::scratch_dir("cli_run_cache");
    fs::remove_all(dir);
    const std::string env = "SOFTCUT_CACHE_DIR='" + (dir / "cache").string() + "' ";
    const std::string scen = softcut::test::source("scenarios/knee_ligament.lua") + " --quiet --frames 12 --no-render";
    // Through sh, with the cache folder in front of the command.
    auto run_env = [&](const std::string& out, const std::string& extra) {
      const std::string cmd = "cd '" SOFTCUT_SOURCE_DIR "' && " + env + "'" SOFTCUT_BIN "' run " + scen + " --out " +
                              (dir / out).string() + extra + " >/dev/null 2>&1";
      return std::system(cmd.c_str());
    };
    CHECK(run_env("cold", "") == 0);
    CHECK(run_env("warm", "") == 0);
    CHECK(run_env("off", " --no-cache") == 0);
    const std::string cold = slurp(dir / "cold" / "summary.json"), warm = slurp(dir / "warm" / "summary.json");
    CHECK(softcut::test::parse_json(cold)["precompute_cache"]["hit"] == false);
    CHECK(softcut::test::parse_json(cold)["precompute_cache"]["miss_reason"] == "no entry");
    CHECK(softcut::test::parse_json(warm)["precompute_cache"]["hit"] == true);
    CHECK(softcut::test::read_json(dir / "off" / "summary.json")["precompute_cache"].is_null());
    CHECK(slurp(dir / "cold" / "displacements.csv") == slurp(dir / "warm" / "displacements.csv"));
    CHECK(slurp(dir / "cold" / "displacements.csv") == slurp(dir / "off" / "displacements.csv"));
    CHECK(!slurp(dir / "cold" / "displacements.csv").empty());
  }

  TEST_CASE("the thread count comes from SOFTCUT_THREADS, else from the idle cores, and is in the summary") {
    const fs::path dir = softcut::test::scratch_dir("cli_run_threads");
    const std::string scen = softcut::test::source("scenarios/knee_ligament.lua") + " --quiet --frames 2 --no-render";
    auto run = [&](const std::string& env, const std::string& out) {
      const std::string cmd = "cd '" SOFTCUT_SOURCE_DIR "' && " + env + " '" SOFTCUT_BIN "' run " + scen + " --out " +
                              (dir / out).string() + " >/dev/null 2>&1";
      CHECK(std::system(cmd.c_str()) == 0);
      return softcut::test::read_json(dir / out / "summary.json")["threads"];
    };
    CHECK(run("SOFTCUT_THREADS=3", "three") ==
          nlohmann::ordered_json{{"count", 3}, {"blas", 3}, {"reason", "SOFTCUT_THREADS=3"}});
    const std::string bad = run("SOFTCUT_THREADS=lots", "bad")["reason"];
    CHECK(bad.starts_with("SOFTCUT_THREADS='lots' ignored (want 1..1024); "));
    CHECK(contains(bad, " idle"));
    const auto automatic = run("env -u SOFTCUT_THREADS", "auto");
    CHECK(contains(automatic["reason"].get<std::string>(), " cores, load "));
    CHECK(automatic["blas"].get<int>() >= 1);
    CHECK(automatic["blas"].get<int>() <= std::min(2, automatic["count"].get<int>()));
  }

  TEST_CASE("--frames out of range names the accepted range") {
    const auto r = run_cli("run " + softcut::test::source("scenarios/upper_leg.lua") + " --frames 99999999999");
    CHECK(r.status == 2);  // a usage error, as --help documents
    CHECK(contains(r.output, "expected a whole number from 0 to 100000000"));
  }

  TEST_CASE("plain progress lines when not on a terminal - --frames - --set") {
    const fs::path dir = softcut::test::scratch_dir("cli_run_lines");
    const auto r = run_cli("run " + softcut::test::source("scenarios/knee_ligament.lua") + " --out " + (dir / "a").string() +
                           " --frames 7 --set force=2");
    CHECK(r.status == 0);
    CHECK(contains(r.output, "frame 7/61"));
    CHECK(contains(r.output, "ETA"));
    CHECK_FALSE(contains(r.output, "\r"));
    CHECK(contains(r.output, "knee_ligament: 7 frames, frame_limit"));
    CHECK(contains(slurp(dir / "a" / "summary.json"), "\"frames\": 7"));
  }

  TEST_CASE("default output folder is renders/<scenario name>/ under the working folder") {
    const fs::path dir = softcut::test::scratch_dir("cli_run_default");
    const auto r = run_cli("run " + softcut::test::source("scenarios/liver_retraction.lua") + " --quiet --frames 2", dir);
    CHECK(r.status == 0);
    CHECK(fs::exists(dir / "renders" / "liver_retraction" / "summary.json"));
  }

  TEST_CASE("usage errors and script errors exit non-zero with one clear message") {
    CHECK(run_cli("run").status == 2);
    const auto bad = run_cli("run x.lua --bogus");
    CHECK(bad.status == 2);  // a usage error, as --help documents
    CHECK(contains(bad.output, "unknown option '--bogus'"));
    const auto set = run_cli("run " + softcut::test::source("scenarios/upper_leg.lua") + " --set poke=1 --quiet");
    CHECK(set.status == 1);
    CHECK(contains(set.output, "upper_leg.lua:7: params: --set poke: the scenario has no parameter 'poke' (did you mean 'poke_force'?)"));
    const fs::path dir = softcut::test::scratch_dir("cli_run_err");
    std::ofstream(dir / "e.lua") << "os.execute('touch " << (dir / "pwned").string() << "')\n";
    const auto esc = run_cli("run " + (dir / "e.lua").string());
    CHECK(esc.status == 1);
    CHECK(contains(esc.output, "e.lua:1: os.execute is not available in the sandbox"));
    CHECK_FALSE(fs::exists(dir / "pwned"));
    // --trust lifts the sandbox.
    std::ofstream(dir / "t.lua") << "assert(type(os.getenv('PATH')) == 'string')\nerror('reached')\n";
    CHECK(contains(run_cli("run " + (dir / "t.lua").string() + " --trust").output, "t.lua:2: reached"));
  }

  TEST_CASE("a run that fails before its outputs exist leaves no earlier run's outputs in --out") {
    const fs::path dir = softcut::test::scratch_dir("cli_run_stale"), out = dir / "out";
    const std::string leg = softcut::test::source("scenarios/upper_leg.lua");
    REQUIRE(run_cli("run " + leg + " --out " + out.string() + " --quiet --frames 2").status == 0);
    REQUIRE(fs::exists(out / "summary.json"));
    std::ofstream(out / "notes.txt") << "mine\n";
    std::ofstream(dir / "broken.lua") << "error('broken before any output')\n";
    const auto r = run_cli("run " + (dir / "broken.lua").string() + " --out " + out.string() + " --quiet");
    CHECK(r.status == 1);
    CHECK(contains(r.output, "broken.lua:1: broken before any output"));
    CHECK_FALSE(fs::exists(out / "summary.json"));  // not the last run's pass
    CHECK_FALSE(fs::exists(out / "displacements.csv"));
    CHECK(slurp(out / "notes.txt") == "mine\n");  // only softcut's own names are cleared
  }

  TEST_CASE("a failed expectation exits 1 after writing the outputs, a met one exits 0") {
    const fs::path dir = softcut::test::scratch_dir("cli_run_expect");
    for (const bool met : {true, false}) {
      const fs::path script = dir / (met ? "met.lua" : "unmet.lua");
      std::ofstream(script) << R"(
local s = softcut.scenario{ name = "bar", duration = 0.1, fps = 10 }
s:mesh{ generate = "box", options = { nx = 4, ny = 1, nz = 1, max = {4, 1, 1} } }
s:material{ tissue = "liver" }
s:fix{ nodes = softcut.select.box{ min = {0, 0, 0}, max = {0, 1, 1} } }
s:expect{ at = 0.1, check = function(f) return )" << (met ? "true" : "false") << R"( end, message = "the check said no" }
return s
)";
      const auto r = run_cli("run " + script.string() + " --out " + (dir / (met ? "met" : "unmet")).string() + " --quiet");
      CHECK(r.status == (met ? 0 : 1));
      CHECK(contains(r.output, "the check said no") == !met);
      CHECK(fs::exists(dir / (met ? "met" : "unmet") / "summary.json"));
    }
    // Cut short by --frames, an expectation not reached is no failure.
    const auto early = run_cli("run " + (dir / "unmet.lua").string() + " --out " + (dir / "early").string() + " --frames 1");
    CHECK(early.status == 0);
    CHECK(contains(early.output, "0 passed, 0 failed, 1 not reached (frame_limit)"));
  }

  TEST_CASE("summary.json records the expectations' values and verdicts, the parameters and the command line") {
    const fs::path dir = softcut::test::scratch_dir("cli_run_summary_expect");
    const fs::path script = dir / "bar.lua";
    std::ofstream(script) << R"(
local P = softcut.params{ f = 0.01, tag = "a" }
local s = softcut.scenario{ name = "bar", duration = 0.4, fps = 10 }
s:mesh{ generate = "box", options = { max = { 0.1, 0.02, 0.02 }, nx = 5, ny = 2, nz = 2 } }
s:material{ young = 5e3, poisson = 0.4 }
s:fix{ nodes = softcut.select.box{ min = { -1, -1, -1 }, max = { 0, 1, 1 } } }
local tip = softcut.select.box{ min = { 0.1, -1, -1 }, max = { 1, 1, 1 } }
s:load{ name = "tip", nodes = tip, force = { 0, 0, -P.f } }
s:expect{ name = "sags", at = 0.2, nodes = tip, component = "z", max = 0 }
s:expect{ name = "counted", at = 0.1, check = function(f) return false, 42 end }
s:expect{ name = "late", at = 0.4, check = function(f) return true end }
return s
)";
    const fs::path out = dir / "out";
    const auto r = run_cli("run " + script.string() + " --out " + out.string() + " --quiet --frames 3 --set f=0.02");
    CHECK(r.status == 1);  // "counted" fails; frames 0, 1, 2 run
    const nlohmann::ordered_json j = softcut::test::read_json(out / "summary.json");
    const std::vector<std::string> cmd = j["command_line"];
    REQUIRE(cmd.size() >= 5);
    CHECK(std::vector<std::string>(cmd.begin(), cmd.begin() + 4) ==
          std::vector<std::string>{"softcut", "run", script.string(), "--out"});
    CHECK(std::vector<std::string>(cmd.end() - 2, cmd.end()) == std::vector<std::string>{"--set", "f=0.02"});
    CHECK(j["params"].dump() == R"({"f":"0.02","tag":"a"})");  // as the file lists them
    CHECK(j["versions"]["build_type"].is_string());
    const nlohmann::ordered_json& e = j["expectations"];
    REQUIRE(e.size() == 3);
    const nlohmann::ordered_json sags = e[0];
    CHECK(sags["name"] == "sags");
    CHECK(sags["where"] == script.string() + ":9");
    CHECK(sags["at_s"] == 0.2);
    CHECK(sags["kind"] == "bounds");
    CHECK(sags["measure"] == "mean");
    CHECK(sags["component"] == "z");
    CHECK(sags["nodes"] == 9);
    CHECK(sags["min"].is_null());
    CHECK(sags["max"] == 0);
    CHECK(sags["reached"] == true);
    CHECK(sags["time_s"] == 0.2);
    CHECK(sags["value"].get<double>() < 0);
    CHECK(sags["pass"] == true);
    CHECK(sags["message"].get<std::string>().starts_with("mean uz of 9 nodes at t = 0.2 s is -"));
    // A check's message that is not a string is shown as text.
    CHECK(e[1] == nlohmann::ordered_json{{"name", "counted"}, {"where", script.string() + ":10"}, {"at_s", 0.1}, {"kind", "check"},
                                 {"min", nullptr}, {"max", nullptr}, {"reached", true}, {"time_s", 0.1},
                                 {"value", nullptr}, {"pass", false}, {"message", "42"}});
    CHECK(e[2] == nlohmann::ordered_json{{"name", "late"}, {"where", script.string() + ":11"}, {"at_s", 0.4}, {"kind", "check"},
                                 {"min", nullptr}, {"max", nullptr}, {"reached", false}, {"time_s", nullptr},
                                 {"value", nullptr}, {"pass", false},
                                 {"message", "not reached: the run ended at t = 0.2 s before at = 0.4 s"}});
  }

  TEST_CASE("SIGTERM finishes the frame, writes valid outputs marked interrupted") {
    const fs::path dir = softcut::test::scratch_dir("cli_run_sigterm");
    // Long enough that the signal lands mid-run: 100000 frames of a tiny box.
    std::ofstream(dir / "long.lua") << R"(
local s = softcut.scenario{ name = "long", duration = 1000, fps = 100 }
s:mesh{ generate = "box", options = { nx = 2, ny = 2, nz = 2 } }
s:material{ tissue = "liver" }
s:fix{ nodes = softcut.select.box{ min = {0, 0, 0}, max = {0, 1, 1} } }
s:load{ nodes = softcut.select.box{ min = {1, 0, 0}, max = {1, 1, 1} }, force = {0, 0, -1}, ramp = softcut.ramp.sine{ amplitude = 1, frequency = 1 } }
s:on_frame(function(f) if f.frame == 20 then local m = io.open("started", "w"); m:write("x"); m:close() end end)
return s
)";
    const pid_t pid = fork();
    REQUIRE(pid >= 0);
    if (pid == 0) {
      freopen("/dev/null", "w", stderr);
      execl(SOFTCUT_BIN, SOFTCUT_BIN, "run", (dir / "long.lua").c_str(), "--out", (dir / "out").c_str(), (char*)nullptr);
      _exit(127);
    }
    for (int i = 0; i < 200 && !fs::exists(dir / "out" / "started"); ++i)
      std::this_thread::sleep_for(std::chrono::milliseconds(25));
    REQUIRE(fs::exists(dir / "out" / "started"));
    kill(pid, SIGTERM);
    int status = 0;
    waitpid(pid, &status, 0);
    CHECK(WIFEXITED(status));
    CHECK(WEXITSTATUS(status) == 130);
    const std::string summary = slurp(dir / "out" / "summary.json");
    CHECK(contains(summary, "\"interrupted\": true"));
    // Every row complete; the last frame logged completely.
    std::istringstream csv(slurp(dir / "out" / "displacements.csv"));
    std::string line;
    std::getline(csv, line);
    CHECK(line == "frame,time,node,ux,uy,uz");
    int rows = 0, last_frame = -1, per_frame = 0, in_last = 0;
    while (std::getline(csv, line)) {
      CHECK(std::count(line.begin(), line.end(), ',') == 5);
      const int frame = std::stoi(line.substr(0, line.find(',')));
      if (frame != last_frame) {
        if (last_frame == 0) per_frame = in_last;
        last_frame = frame, in_last = 0;
      }
      ++in_last, ++rows;
    }
    CHECK(last_frame >= 20);
    CHECK(last_frame < 100000 - 1);
    CHECK(in_last == per_frame);
  }

  // Issue #38 item 17 and #40 items 7-8: mistakes a user makes, each run
  // through the CLI; the message names the file:line and what to do, and no
  // raw Lua wording or softcut's own frames are shown.
  TEST_CASE("mistakes get a message with file:line and what to do, not Lua's raw wording") {
    const std::string head = R"(local s = softcut.scenario{ name = "msg", duration = 0.2, fps = 10 }
s:mesh{ generate = "box", options = { min = {0, 0, 0}, max = {0.1, 0.04, 0.04}, nx = 2, ny = 1, nz = 1 } }
s:material{ tissue = "liver" }
s:fix{ nodes = softcut.select.box{ min = {0, 0, 0}, max = {0, 0.04, 0.04} } }
local tip = softcut.select.box{ min = {0.1, 0, 0}, max = {0.1, 0.04, 0.04} }
)";
    struct Case {
      const char* what;
      std::string tail;                 // line 6 on
      std::vector<std::string> wanted;  // in the output
      std::vector<std::string> unwanted;
    };
    const std::vector<Case> cases = {
        {"a force whose length overflows", "s:load{ nodes = tip, force = {0, 0, -1e300} }\n",
         {"s.lua:6: load: field 'force' (length 1e+300 N) reaches 1e+300 N", "bound"}, {"'to'", "ramp"}},
        {"a force times its ramp", "s:load{ nodes = tip, force = {0, 0, -2}, ramp = softcut.ramp.linear{ t1 = 1, to = 1e7 } }\n",
         {"s.lua:6: load: field 'force' (length 2 N) times field 'ramp' (up to 1e+07) reaches 2e+07 N"}, {}},
        {"error({}) in on_frame", "s:on_frame(function(f) error({}) end)\n",
         {"s.lua:6: error raised with table as its message", "error(\"what went wrong\")"}, {"table: 0x"}},
        {"string.rep of 2^40", "local x = string.rep('x', 2^40)\n",
         {"s.lua:6: string.rep: memory budget of 512 MiB exceeded: the result would take 1.1e+12 bytes", "--trust"},
         {"resulting string too large"}},
        {"load of a binary chunk", "local f = load(string.dump(function() end))\n",
         {"s.lua:6: load: binary chunks are refused"}, {}},
        {"a misspelled Scenario method", "s:grasp{ name = 'jaw', path = {0, 0, 0}, stiffness = 1 }\n",
         {"s.lua:6: Scenario has no method 'grasp' (did you mean 'grasper'?)", "s.lua:6: in main chunk"},
         {"attempt to call a nil value", "softcut/", "[C]"}},
        {"a misspelled selection", "s:fix{ nodes = softcut.select.sphre{ center = {0, 0, 0}, radius = 1 } }\n",
         {"s.lua:6: softcut.select has no function 'sphre' (did you mean 'sphere'?)"}, {"attempt to call"}},
        {"a misspelled Frame method", "s:on_frame(function(f)\n  local d = f:max_displacment(tip)\nend)\n",
         {"s.lua:7: Frame has no method 'max_displacment' (did you mean 'max_displacement'?)",
          "s.lua:7: in function <s.lua:6>"},
         {"attempt to call", "softcut/scenario.lua", "[C]"}},
        {"elevation 90", "s:output{ render = { elevation = 90 } }\n",
         {"s.lua:6: output: field 'render': field 'elevation' = 90 deg is out of range: must be < 90 deg"},
         {"elevation_deg"}},
        {"elevation 90 set after the checks", "s:output{ render = { elevation = 10 } }\ns._output.render.elevation = 90\n",
         {"s.lua:6: output: render: elevation must lie in (-90, 90) degrees, got 90"}, {"elevation_deg"}},
    };
    const fs::path dir = softcut::test::scratch_dir("cli_run_messages");
    for (const Case& c : cases) {
      CAPTURE(c.what);
      std::ofstream(dir / "s.lua") << head << c.tail << "return s\n";
      const auto r = run_cli("run s.lua --no-render --out out", dir);
      INFO(r.output);
      CHECK(r.status == 1);
      for (const auto& w : c.wanted) CHECK(contains(r.output, w));
      for (const auto& u : c.unwanted) CHECK_FALSE(contains(r.output, u));
    }
  }

  TEST_CASE("require of a binary module and a 300-deep require chain name the module and the file") {
    const fs::path dir = softcut::test::scratch_dir("cli_run_require");
    std::ofstream(dir / "bin.lua") << "\x1bLua\x54\x00 not really bytecode";
    std::ofstream(dir / "s.lua") << "local m = require 'bin'\n";
    const auto r = run_cli("run s.lua --no-render --out out", dir);
    INFO(r.output);
    CHECK(r.status == 1);
    CHECK(contains(r.output, "s.lua:1: require 'bin': "));
    CHECK(contains(r.output, (dir / "bin.lua").string() + " is a precompiled (binary) Lua chunk"));
    for (int i = 1; i <= 300; ++i) std::ofstream(dir / ("m" + std::to_string(i) + ".lua")) << "return require 'm" << i + 1 << "'\n";
    std::ofstream(dir / "m301.lua") << "return 1\n";
    std::ofstream(dir / "chain.lua") << "local m = require 'm1'\n";
    const auto c = run_cli("run chain.lua --no-render --out out", dir);
    INFO(c.output);
    CHECK(c.status == 1);
    CHECK(contains(c.output, "m50.lua:1: require 'm51' (" + (dir / "m51.lua").string() + ")"));
    CHECK(contains(c.output, "require each other 50 deep"));
    CHECK_FALSE(contains(c.output, "stack overflow"));
  }

  TEST_CASE("softcut --help lists every mesh generator") {
    const auto r = run_cli("--help");
    CHECK(r.status == 0);
    for (const char* kind : {"box", "cylinder", "tube", "band", "ligament", "upper_leg", "liver", "kidney",
                             "knee_ligament", "volume"})
      CHECK(contains(r.output, kind));
  }
  TEST_CASE("tools that did nothing say so, with their closest approach, codes on stderr and in summary.json") {
    const fs::path dir = softcut::test::scratch_dir("cli_run_idle_tools");
    // A 100 x 40 x 40 mm bar; each tool misses it, or touches without cutting.
    std::ofstream(dir / "idle.lua") << R"(
local s = softcut.scenario{ name = "idle", duration = 1.0, fps = 10 }
s:mesh{ generate = "box", options = { max = { 0.1, 0.04, 0.04 }, nx = 5, ny = 2, nz = 2 } }
s:material{ tissue = "liver" }
s:fix{ nodes = softcut.select.box{ min = { -1, -1, -1 }, max = { 0, 1, 1 } } }
s:operational{ box = { min = { 0.05, -1, -1 }, max = { 1, 1, 1 } } }
s:probe{ name = "tip", path = softcut.path.fixed{ 0.05, 0.02, 0.06 }, radius = 0.004, force = 0.1 }
s:grasper{ name = "jaw", path = softcut.path.polyline{ times = { 0, 0.5, 1 },
           points = { { 0.02, 0.02, 0.08 }, { 0.02, 0.02, 0.0523 }, { 0.02, 0.02, 0.08 } } }, stiffness = 100 }
s:scalpel{ name = "blade", path = softcut.path.fixed{ 0.03, 0.02, 0.0523 }, cut_pressure = 1e3, force = 0.1 }
s:scalpel{ name = "dull", path = softcut.path.polyline{ times = { 0, 1 }, points = { { 0.08, 0.02, 0.045 }, { 0.08, 0.02, 0.0395 } } },
           cut_pressure = 1e9, force = 0.05 }
s:probe{ name = "late", path = softcut.path.fixed{ 0.05, 0.02, 0.04 }, radius = 0.004, force = 0.1, start = 3 }
s:probe{ name = "pokes", path = softcut.path.fixed{ 0.09, 0.02, 0.041 }, radius = 0.004, force = 0.1 }
return s
)";
    const auto r = run_cli("run idle.lua --out out --no-render", dir);
    INFO(r.output);
    CHECK(r.status == 0);
    const std::vector<std::string> expected = {
        "idle.lua:7: probe 'tip' never touched the tissue (closest 16 mm at t = 0 s); move its path onto the surface "
        "or give it a larger radius [tool_never_touched]",
        "idle.lua:8: grasper 'jaw' never touched the tissue (closest 8.25 mm at t = 0.5 s), so it never closed; move "
        "its path onto the surface or give it a larger radius [tool_never_touched]",
        "idle.lua:10: scalpel 'blade' never touched the tissue (closest 11.3 mm at t = 0 s); move its path onto the "
        "surface [tool_never_touched]",
        "idle.lua:11: scalpel 'dull' touched the tissue but never cut: its contact pressure peaked at 1.25 kPa at "
        "t = 0.8 s, below its cut_pressure = 1e+03 MPa; press harder (force or stiffness) or lower cut_pressure "
        "[scalpel_never_cut]",
        "idle.lua:13: probe 'late' was never active: its start = 3 s comes after the run's last frame at t = 1 s; "
        "start it earlier or run longer [tool_never_active]"};
    for (const std::string& w : expected) CHECK(contains(r.output, "warning: " + w + "\n"));
    CHECK_FALSE(contains(r.output, "'pokes'"));  // it touched
    // The tools' warnings, in order; the poking probe also bends the liver
    // bar past the linear law's 5 deg (sim/validity), said after them.
    const nlohmann::ordered_json j = softcut::test::read_json(dir / "out" / "summary.json");
    REQUIRE(j["warnings"].size() == expected.size() + 1);
    for (size_t k = 0; k < expected.size(); ++k) CHECK(j["warnings"][k] == expected[k]);
    CHECK(softcut::warning_code(j["warnings"].back().get<std::string>()) == "linear_large_rotation");
    // --warnings-as-errors: exit 1, saying why; -q still says it.
    const auto strict = run_cli("run idle.lua --out out --no-render -q --warnings-as-errors", dir);
    CHECK(strict.status == 1);
    CHECK(contains(strict.output, "softcut: error: idle: 6 warnings with --warnings-as-errors: " + expected[0]));
    // Cut short by --frames, the tools had no chance: nothing said of them.
    const auto early = run_cli("run idle.lua --out early --no-render --frames 3", dir);
    CHECK(early.status == 0);
    const auto early_summary = softcut::test::read_json(dir / "early" / "summary.json");
    for (const auto& w : early_summary["warnings"])
      CHECK(softcut::warning_code(w.get<std::string>()) == "linear_large_rotation");
  }
  TEST_CASE("an implausible material warns at its line, naming the nearest preset and the unit it suggests") {
    const fs::path dir = softcut::test::scratch_dir("cli_run_material");
    std::ofstream(dir / "kidney.lua") << R"(
local s = softcut.scenario{ name = "kidney", duration = 0.1, fps = 10 }
s:mesh{ generate = "box", options = { max = { 0.1, 0.04, 0.04 }, nx = 5, ny = 2, nz = 2 } }
s:material{ name = "cortex", young = 20.7, poisson = 0.45 }
s:fix{ nodes = softcut.select.box{ min = { -1, -1, -1 }, max = { 0, 1, 1 } } }
return s
)";
    const std::string warning =
        "kidney.lua:4: material 'cortex': young = 20.7 Pa is far below every tissue preset (fat 3.25 kPa .. ligament "
        "11 MPa); the nearest is 'fat' (3.25 kPa); kPa given as Pa? young = 20700 (20.7 kPa) is near 'kidney' "
        "(20.7 kPa). Young's modulus is in Pa [implausible_material]";
    const auto r = run_cli("run kidney.lua --out out --no-render", dir);
    INFO(r.output);
    CHECK(r.status == 0);
    CHECK(contains(r.output, "warning: " + warning + "\n"));
    CHECK(softcut::test::read_json(dir / "out" / "summary.json")["warnings"] == nlohmann::ordered_json::array({warning}));
    CHECK(run_cli("run kidney.lua --out out --no-render --warnings-as-errors", dir).status == 1);
  }
}
