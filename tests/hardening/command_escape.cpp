// `softcut check`, `sweep` and `sweep merge` attacked the way an outsider
// would (issue #38): a scenario package or sweep folder someone else
// prepared, a hostile local user, a CI runner that kills or limits the job.
// Each case is one item of the issue and must end with a clear error (or a
// bounded, reported result), never a file touched outside the output
// folder, an outside file's bytes in a report, a hang, an orphaned process
// or a crash.
#include <doctest/doctest.h>
#include <signal.h>
#include <sys/file.h>
#include <sys/resource.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <fcntl.h>
#include <fstream>
#include <functional>
#include <sstream>
#include <nlohmann/json.hpp>
#include <string>
#include <thread>
#include <vector>

#include "app/scenario_run.hpp"
#include "cli_test_support.hpp"
#include "app/sweep_plan.hpp"
#include "hardening_support.hpp"

namespace fs = std::filesystem;
using softcut::hardening::contains;
using softcut::hardening::count_files;
using softcut::hardening::put_file;
using softcut::hardening::run_softcut;
using softcut::test::slurp;

namespace {

// A small fast scenario (a bar pulled at its tip): `extra` Lua goes before
// `return s`; `duration` s at `fps`.
std::string bar(const std::string& name, const std::string& extra = "", const std::string& duration = "0.2",
                const std::string& fps = "10") {
  return "local P = softcut.params{ f = 0.01 }\n"
         "local s = softcut.scenario{ name = '" + name + "', duration = " + duration + ", fps = " + fps + " }\n"
         "s:mesh{ generate = 'box', options = { max = { 0.1, 0.02, 0.02 }, nx = 5, ny = 2, nz = 2 } }\n"
         "s:material{ young = 5e3, poisson = 0.4 }\n"
         "s:fix{ nodes = softcut.select.box{ min = { -1, -1, -1 }, max = { 0, 1, 1 } } }\n"
         "s:load{ name = 'tip', nodes = softcut.select.box{ min = { 0.1, -1, -1 }, max = { 1, 1, 1 } },\n"
         "        force = { 0, 0, -P.f } }\n" + extra + "\nreturn s\n";
}

// The files an earlier run leaves in an output folder: what a wrongly
// cleared folder would lose.
void plant_outputs(const fs::path& dir) {
  fs::create_directories(dir / "frames");
  fs::create_directories(dir / "vtu");
  put_file(dir / "summary.json", "victim summary");
  put_file(dir / "displacements.csv", "victim log");
  put_file(dir / "frames" / "frame_000000.png", "victim frame");
  put_file(dir / "vtu" / "frame_000000.vtu", "victim vtu");
}

bool outputs_intact(const fs::path& dir) {
  return slurp(dir / "summary.json") == "victim summary" && slurp(dir / "displacements.csv") == "victim log" &&
         slurp(dir / "frames" / "frame_000000.png") == "victim frame" &&
         slurp(dir / "vtu" / "frame_000000.vtu") == "victim vtu";
}

// softcut ARGS run directly (no shell) in `cwd`, stdout and stderr into
// `log`: exit status and the process's own peak RSS and wall time.
struct Measured {
  int status = -1;
  long long peak_rss = 0;  // bytes
  double seconds = 0;
  std::string output;
};
Measured exec_softcut(const std::vector<std::string>& args, const fs::path& cwd, double timeout_s = 120) {
  const fs::path log = cwd / ("exec-" + std::to_string(::getpid()) + ".log");
  const auto t0 = std::chrono::steady_clock::now();
  std::fflush(nullptr);
  const pid_t pid = ::fork();
  if (pid == 0) {
    if (::chdir(cwd.c_str()) != 0) ::_exit(126);
    const int fd = ::open(log.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
    ::dup2(fd, 1), ::dup2(fd, 2);
    std::vector<char*> argv = {const_cast<char*>(SOFTCUT_BIN)};
    for (const auto& a : args) argv.push_back(const_cast<char*>(a.c_str()));
    argv.push_back(nullptr);
    ::execv(SOFTCUT_BIN, argv.data());
    ::_exit(127);
  }
  Measured m;
  int st = 0;
  rusage ru{};
  for (;;) {
    const pid_t w = ::wait4(pid, &st, WNOHANG, &ru);
    m.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    if (w == pid) break;
    if (m.seconds > timeout_s) ::kill(pid, SIGKILL);  // a hang fails the test, it does not hang ctest
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
  }
  m.status = WIFEXITED(st) ? WEXITSTATUS(st) : 128 + WTERMSIG(st);
  m.peak_rss = (long long)ru.ru_maxrss * 1024;
  m.output = slurp(log);
  fs::remove(log);
  return m;
}

// A sweep folder made by hand: the plan of `runs` runs of key f and, per
// run, a summary whose text `summary(i)` gives (empty: none).
void write_sweep(const fs::path& dir, std::size_t runs, const std::function<std::string(std::size_t)>& summary) {
  softcut::app::SweepPlan plan;
  plan.scenario = (dir / "s.lua").string();
  plan.keys = {"f"};
  plan.runs.resize(runs);
  for (std::size_t i = 0; i < runs; ++i) plan.runs[i].params = {{"f", std::to_string(i)}};
  softcut::app::number_runs(plan.runs);
  fs::create_directories(dir);
  put_file(dir / "sweep_plan.json", softcut::app::plan_json(plan));
  for (std::size_t i = 0; i < runs; ++i) {
    const std::string text = summary(i);
    if (text.empty()) continue;
    fs::create_directories(dir / plan.runs[i].id);
    put_file(dir / plan.runs[i].id / "summary.json", text);
  }
}

// A summary as `softcut run` writes it (the fields merge reads), run with --set f=<i>.
nlohmann::json summary_of(std::size_t i, const std::string& message = "") {
  return {{"schema", "softcut-summary/1"},
          {"command_line", {"softcut", "run", "s.lua", "--set", "f=" + std::to_string(i)}},
          {"run", {{"frames", 3}, {"last_time_s", 0.2}, {"exit_reason", "completed"}, {"message", message}}},
          {"expectations", nlohmann::json::array()}};
}

// Processes whose parent is `pid` (from /proc).
std::vector<pid_t> children_of(pid_t pid) {
  std::vector<pid_t> out;
  std::error_code ec;
  for (const auto& e : fs::directory_iterator("/proc", ec)) {
    const std::string name = e.path().filename().string();
    if (name.find_first_not_of("0123456789") != std::string::npos) continue;
    std::ifstream in(e.path() / "stat");
    std::string stat;
    std::getline(in, stat);
    const auto close = stat.rfind(')');
    if (close == std::string::npos) continue;
    std::istringstream rest(stat.substr(close + 2));
    char state = 0;
    long ppid = 0;
    rest >> state >> ppid;
    if (ppid == pid) out.push_back(pid_t(std::stol(name)));
  }
  return out;
}

// Alive: in /proc and not a zombie.
bool alive(pid_t pid) {
  std::ifstream in("/proc/" + std::to_string(pid) + "/stat");
  std::string stat;
  if (!std::getline(in, stat)) return false;
  const auto close = stat.rfind(')');
  return close != std::string::npos && close + 2 < stat.size() && stat[close + 2] != 'Z';
}

}  // namespace

TEST_SUITE("hardening/command_escape") {
  // 1. Critical: check cleared the folder a scenario names before refusing it.
  TEST_CASE("item 1: check never clears or makes a folder a scenario's name points at") {
    const fs::path root = softcut::test::scratch_dir("cmd_esc_name");
    const fs::path victim = root / "victim";
    plant_outputs(victim);
    fs::create_directories(root / "pkg");
    fs::create_directories(root / "a" / "b");
    put_file(root / "pkg" / "abs.lua", bar("abs", "s.name = '" + victim.string() + "'"));
    put_file(root / "pkg" / "up.lua", bar("up", "s.name = '../../victim'"));
    put_file(root / "pkg" / "dot.lua", bar("dot", "s.name = '..'"));
    for (const std::string& out : std::vector<std::string>{"", " --out " + (root / "a" / "b").string()}) {
      const auto r = run_softcut("check " + (root / "pkg").string() + out, root);
      INFO(r.output);
      CHECK(r.status == 1);
      CHECK(contains(r.output, "0 passed, 3 failed"));
      CHECK(contains(r.output, "abs.lua: scenario '" + victim.string() + "': name must not contain path separators"));
      CHECK(contains(r.output, "up.lua: scenario '../../victim': name must not contain path separators"));
      CHECK(contains(r.output, "dot.lua: scenario '..': name must not be '.' or '..'"));
      CHECK(outputs_intact(victim));
    }
    CHECK(fs::is_empty(root / "a" / "b"));  // nothing made for the refused names
  }

  TEST_CASE("item 1: a link planted at --out DIR/<name> is refused, not written through or cleared") {
    const fs::path root = softcut::test::scratch_dir("cmd_esc_outlink");
    const fs::path victim = root / "victim";
    plant_outputs(victim);
    put_file(root / "s.lua", bar("linked"));
    fs::create_directories(root / "out");
    fs::create_directory_symlink(victim, root / "out" / "linked");
    const auto r = run_softcut("check s.lua --out out", root);
    INFO(r.output);
    CHECK(r.status == 1);
    CHECK(contains(r.output, "'linked' is a symbolic link"));
    CHECK(outputs_intact(victim));
  }

  // 2. The temporary output root was softcut-check-<pid>, made with
  // create_directories (mode 0755, following a link planted under that name).
  TEST_CASE("item 2: check's temporary root is a fresh private folder, not a predictable one a link can stand in for") {
    const fs::path root = softcut::test::scratch_dir("cmd_esc_tmp");
    const fs::path victim = root / "victim";
    plant_outputs(victim);
    fs::create_directories(root / "tmp");
    put_file(root / "s.lua", bar("tmpcheck", "", "300", "30"));  // 9000 frames: ~0.5 s in Release, for the watcher to see
    // The shell plants the link under the name its own pid gives, then becomes
    // softcut (exec keeps the pid); a watcher prints the mode of the folder made.
    const std::string tmp = (root / "tmp").string();
    const auto r = softcut::test::run_cli_raw(
        "cd '" + root.string() + "' && export TMPDIR='" + tmp + "' && sh -c '"
        "ln -s \"" + victim.string() + "\" \"$TMPDIR/softcut-check-$$\"; "
        "(for i in $(seq 3000); do for d in \"$TMPDIR\"/softcut-check-??????; do "
        "if [ -d \"$d\" ] && [ ! -L \"$d\" ]; then stat -c \"mode %a\" \"$d\"; exit; fi; done; sleep 0.01; done) & "
        "exec " SOFTCUT_BIN " check s.lua --record'");
    INFO(r.output);
    CHECK(contains(r.output, "PASS  s.lua"));
    CHECK(contains(r.output, "mode 700"));
    CHECK(outputs_intact(victim));
    CHECK(!fs::exists(victim / "tmpcheck"));  // the run did not write through the link
    int left = 0;  // the planted link stays; softcut's own folder is gone
    for (const auto& e : fs::directory_iterator(root / "tmp")) left += !fs::is_symlink(e.symlink_status());
    CHECK(left == 0);
  }

  // 3. Reference logs were read with std::ifstream.
  TEST_CASE("item 3: a linked, FIFO, device or huge reference log is refused at once, its bytes never reported") {
    const fs::path root = softcut::test::scratch_dir("cmd_esc_ref");
    put_file(root / "s.lua", bar("refs"));
    REQUIRE(run_softcut("check s.lua --record", root).status == 0);
    // A secret of 3 lines: a link to it must not report its row count or rows.
    put_file(root / "secret.csv", "frame,time,node,ux,uy,uz\n0,0,4242,1,2,3\n1,0.1,4242,1,2,3\n");
    fs::remove(root / "s.ref.csv");
    fs::create_symlink(root / "secret.csv", root / "s.ref.csv");
    const auto link = run_softcut("check s.lua", root);
    INFO(link.output);
    CHECK(link.status == 1);
    CHECK(contains(link.output, "'s.ref.csv' is a symbolic link"));
    CHECK(!contains(link.output, "4242"));
    CHECK(!contains(link.output, " rows"));
    fs::remove(root / "s.ref.csv");
    fs::create_symlink("/dev/zero", root / "s.ref.csv");
    CHECK(contains(run_softcut("check s.lua", root).output, "'s.ref.csv' is a symbolic link"));
    fs::remove(root / "s.ref.csv");
    REQUIRE(::mkfifo((root / "s.ref.csv").c_str(), 0644) == 0);
    const auto fifo = exec_softcut({"check", "s.lua"}, root, 60);  // blocked forever before
    INFO(fifo.output);
    CHECK(fifo.status == 1);
    CHECK(contains(fifo.output, "'s.ref.csv' is not a regular file"));
    CHECK(fifo.seconds < 50);
    fs::remove(root / "s.ref.csv");
    // 16 GB of zeros (sparse): refused at its first 64 KiB, not read into memory.
    {
      const int fd = ::open((root / "s.ref.csv").c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
      REQUIRE(fd >= 0);
      REQUIRE(::ftruncate(fd, off_t(16) << 30) == 0);
      ::close(fd);
    }
    const auto zeros = exec_softcut({"check", "s.lua"}, root, 60);
    INFO(zeros.output);
    CHECK(zeros.status == 1);
    CHECK(contains(zeros.output, "s.ref.csv:1: a line longer than 65536 bytes"));
    CHECK(zeros.peak_rss < (512ll << 20));
    // A reference of 200 MB of blank lines is read no further than the log allows.
    {
      std::ofstream big(root / "s.ref.csv", std::ios::trunc);
      const std::string mb(1 << 20, '\n');
      for (int k = 0; k < 200; ++k) big << mb;
    }
    const auto blank = exec_softcut({"check", "s.lua"}, root, 60);
    INFO(blank.output);
    CHECK(blank.status == 1);
    CHECK(contains(blank.output, "over twice the log it is compared with"));
  }

  // 4. check DIR ran a *.lua that is a link, and Lua quoted its first token.
  TEST_CASE("item 4: check DIR runs no linked or non-regular *.lua, and quotes nothing of it") {
    const fs::path root = softcut::test::scratch_dir("cmd_esc_linked_lua");
    put_file(root / "secret.txt", "TOPSECRET_TOKEN hunter2\n");  // Lua: "syntax error near 'hunter2'"
    fs::create_directories(root / "pkg");
    put_file(root / "pkg" / "ok.lua", bar("fine"));
    fs::create_symlink(root / "secret.txt", root / "pkg" / "evil.lua");
    REQUIRE(::mkfifo((root / "pkg" / "pipe.lua").c_str(), 0644) == 0);
    const auto r = exec_softcut({"check", "--record", "pkg"}, root, 60);
    INFO(r.output);
    CHECK(r.status == 1);
    CHECK(contains(r.output, "FAIL  pkg/evil.lua: pkg/evil.lua is a symbolic link"));
    CHECK(contains(r.output, "FAIL  pkg/pipe.lua: pkg/pipe.lua is not a regular file"));
    CHECK(contains(r.output, "PASS  pkg/ok.lua"));
    CHECK(!contains(r.output, "TOPSECRET"));
    CHECK(!contains(r.output, "hunter2"));
    // Named on the command line, a link is refused too.
    const auto named = run_softcut("check pkg/evil.lua", root);
    CHECK(named.status == 1);
    CHECK(!contains(named.output, "TOPSECRET"));
    // Folders nested past 32 levels are a usage error, not searched without end or skipped silently.
    fs::path deep = root / "deep";
    for (int k = 0; k < 40; ++k) deep /= "d";
    fs::create_directories(deep);
    put_file(deep / "x.lua", bar("deep"));
    const auto nested = run_softcut("check deep", root);
    CHECK(nested.status == 2);
    CHECK(contains(nested.output, "has folders nested more than 32 deep"));
  }

  TEST_CASE("item 4: a scenario swapped for a link after it was listed is still not read through it") {
    // What check's runs do: the scenario is read below the folder named, by the checked open.
    const fs::path root = softcut::test::scratch_dir("cmd_esc_swap");
    put_file(root / "secret.txt", "TOPSECRET_TOKEN = 1\n");
    fs::create_directories(root / "pkg");
    fs::create_symlink(root / "secret.txt", root / "pkg" / "a.lua");
    softcut::app::RunRequest req;
    req.scenario = root / "pkg" / "a.lua";
    req.scenario_root = root / "pkg";
    const std::string msg = softcut::test::error_of([&] { softcut::app::load_scenario_spec(req); });
    CHECK(contains(msg, "'a.lua' is a symbolic link"));
    CHECK(!contains(msg, "TOPSECRET"));
    fs::remove(root / "pkg" / "a.lua");
    fs::create_directories(root / "real");
    put_file(root / "real" / "a.lua", bar("a"));
    fs::create_directory_symlink(root / "real", root / "pkg" / "sub");  // a linked folder below the root
    req.scenario = root / "pkg" / "sub" / "a.lua";
    CHECK(contains(softcut::test::error_of([&] { softcut::app::load_scenario_spec(req); }), "'sub' is a symbolic link"));
  }

  // 5. merge followed a linked run_NNNN folder and copied its summary's message.
  TEST_CASE("item 5: sweep merge refuses a linked run folder or summary, never copying what it points at") {
    const fs::path root = softcut::test::scratch_dir("cmd_esc_merge_link");
    write_sweep(root / "s", 2, [](std::size_t i) { return i == 0 ? summary_of(0).dump() : std::string(); });
    fs::create_directories(root / "elsewhere");
    put_file(root / "elsewhere" / "summary.json", summary_of(1, "TOPSECRET message").dump());
    fs::create_directory_symlink(root / "elsewhere", root / "s" / "run_0001");
    const auto r = run_softcut("sweep merge s", root);
    INFO(r.output);
    CHECK(r.status == 1);
    CHECK(contains(r.output, "'run_0001' is a symbolic link"));
    CHECK(!fs::exists(root / "s" / "sweep.json"));
    fs::remove(root / "s" / "run_0001");
    fs::create_directories(root / "s" / "run_0001");
    fs::create_symlink(root / "elsewhere" / "summary.json", root / "s" / "run_0001" / "summary.json");
    const auto leaf = run_softcut("sweep merge s", root);
    CHECK(leaf.status == 1);
    CHECK(contains(leaf.output, "'summary.json' is a symbolic link"));
    CHECK(!fs::exists(root / "s" / "sweep.json"));
  }

  // 8. A crafted folder: a plan repeating one run, 40,000 expectation names, a missing field.
  TEST_CASE("item 8: a plan listing one run 300,000 times is refused at once with bounded memory") {
    const fs::path root = softcut::test::scratch_dir("cmd_esc_merge_plan");
    write_sweep(root / "s", 1, [](std::size_t i) { return summary_of(i).dump(); });
    nlohmann::json plan = nlohmann::json::parse(slurp(root / "s" / "sweep_plan.json"));
    const nlohmann::json one = plan["runs"][0];
    plan["runs"] = nlohmann::json::array();
    for (int k = 0; k < 300000; ++k) plan["runs"].push_back(one);
    put_file(root / "s" / "sweep_plan.json", plan.dump());
    const auto r = exec_softcut({"sweep", "merge", "s"}, root, 120);
    INFO(r.output);
    CHECK(r.status == 1);
    CHECK(contains(r.output, "sweep_plan.json: not a sweep plan written by softcut sweep: more than 100000 runs"));
    CHECK(r.peak_rss < (600ll << 20));
    // The same id twice among few runs is refused naming the entry.
    plan["runs"] = {one, one};
    put_file(root / "s" / "sweep_plan.json", plan.dump());
    CHECK(contains(run_softcut("sweep merge s", root).output, "'runs[1].id' is 'run_0000', not 'run_0001'"));
  }

  TEST_CASE("item 8: summaries with thousands of expectation names merge in seconds - 40,000 are refused") {
    const fs::path root = softcut::test::scratch_dir("cmd_esc_merge_names");
    auto with_names = [](std::size_t i, int names) {
      nlohmann::json s = summary_of(i);
      for (int k = 0; k < names; ++k)
        s["expectations"].push_back({{"name", "e" + std::to_string(k)}, {"pass", true}, {"reached", true},
                                     {"value", k}, {"message", ""}});
      return s.dump();
    };
    write_sweep(root / "s", 60, [&](std::size_t i) { return with_names(i, 10000); });
    const auto ok = exec_softcut({"sweep", "merge", "s"}, root, 120);
    INFO(ok.output);
    CHECK(ok.status == 0);
    CHECK(contains(ok.output, "merged 60 runs: 60 passed, 0 failed"));
    CHECK(ok.seconds < 60);  // minutes before (linear searches per name and row)
    write_sweep(root / "t", 2, [&](std::size_t i) { return with_names(i, 40000); });
    const auto many = exec_softcut({"sweep", "merge", "t"}, root, 120);
    INFO(many.output);
    CHECK(many.status == 1);
    CHECK(contains(many.output, "run_0000/summary.json: not a summary softcut wrote: 'expectations' lists 40000 "
                                "expectations, more than the 10000 a scenario may declare"));
  }

  TEST_CASE("item 8: a summary missing a field or of the wrong type names the file and the field, exit 1") {
    const fs::path root = softcut::test::scratch_dir("cmd_esc_merge_field");
    struct Case {
      std::function<void(nlohmann::json&)> edit;
      std::string field;
    };
    const std::vector<Case> cases = {
        {[](nlohmann::json& s) { s["run"].erase("exit_reason"); }, "'run.exit_reason' is missing"},
        {[](nlohmann::json& s) { s["run"]["frames"] = "three"; }, "'run.frames' is not a number"},
        {[](nlohmann::json& s) { s.erase("command_line"); }, "'command_line' is missing"},
        {[](nlohmann::json& s) { s["expectations"] = {{{"pass", true}, {"reached", true}}}; },
         "'expectations[0].name' is missing"},
        {[](nlohmann::json& s) { s["expectations"] = {{{"name", "x"}, {"pass", 1}, {"reached", true}}}; },
         "'expectations[0].pass' is not true or false"},
        {[](nlohmann::json& s) { s["run"] = 5; }, "'run' is not an object"},
        {[](nlohmann::json& s) { s["cutting"] = {{"events", "many"}}; }, "'cutting.events' is not a number"},
    };
    for (const Case& c : cases) {
      write_sweep(root / "s", 1, [&](std::size_t i) {
        nlohmann::json s = summary_of(i);
        c.edit(s);
        return s.dump();
      });
      const auto r = run_softcut("sweep merge s", root);
      INFO(r.output);
      CHECK(r.status == 1);
      CHECK(contains(r.output, "s/run_0000/summary.json: not a summary softcut wrote: " + c.field));
      CHECK(!contains(r.output, "internal error"));
    }
    put_file(root / "s" / "run_0000" / "summary.json", "[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[]]]]]]]]]]]]]]]]]]]]]]]]]]]]]]]]]]]]]]]]");
    CHECK(contains(run_softcut("sweep merge s", root).output, "nested deeper than 16 levels"));
  }

  // 16. Table values that are not UTF-8 read alike; over-long ones failed to spawn.
  TEST_CASE("item 16: table and grid values that are not UTF-8, hold control bytes or are over-long are refused naming the line") {
    const fs::path root = softcut::test::scratch_dir("cmd_esc_table");
    put_file(root / "s.lua", bar("table"));
    put_file(root / "bad.csv", "f\n0.01\n0.0\xff" "2\n");
    const auto utf = run_softcut("sweep s.lua --table bad.csv --out o", root);
    INFO(utf.output);
    CHECK(utf.status == 1);
    CHECK(contains(utf.output, "bad.csv:3: the value of 'f' is not UTF-8 text (byte 4 is 0xFF)"));
    put_file(root / "long.csv", "f\n0.01\n" + std::string(200 << 10, '1') + "\n");
    const auto big = run_softcut("sweep s.lua --table long.csv --out o", root);
    CHECK(big.status == 1);
    CHECK(contains(big.output, "long.csv:3: the value of 'f' is 204800 bytes long, more than 4096"));
    put_file(root / "ctl.csv", "f\n0.0\x1b[31m1\n");  // a terminal escape
    CHECK(contains(run_softcut("sweep s.lua --table ctl.csv --out o", root).output,
                   "ctl.csv:2: the value of 'f' holds a control character (byte 4)"));
    const auto grid = run_softcut("sweep s.lua --grid \"$(printf 'f=1,\\376')\" --out o", root);
    CHECK(grid.status == 2);
    CHECK(contains(grid.output, "value 2 of 'f' is not UTF-8 text"));
    CHECK(!fs::exists(root / "o"));
  }

  // 9. Killing the sweep's process group left every run orphaned and busy.
  TEST_CASE("item 9: runs die with a sweep killed by SIGKILL, not orphaned") {
    const fs::path root = softcut::test::scratch_dir("cmd_esc_orphans");
    // 20,000 frames, each with 10^6 Lua instructions: minutes.
    put_file(root / "slow.lua",
             bar("slow", "s:on_frame(function(f) local x = 0 for i = 1, 1e6 do x = x + i end end)", "200", "100"));
    std::fflush(nullptr);
    const pid_t sweep = ::fork();
    if (sweep == 0) {
      ::setpgid(0, 0);  // its own group, as a CI job's
      if (::chdir(root.c_str()) != 0) ::_exit(126);
      const int fd = ::open("sweep.log", O_WRONLY | O_CREAT | O_TRUNC, 0644);
      ::dup2(fd, 1), ::dup2(fd, 2);
      ::execl(SOFTCUT_BIN, SOFTCUT_BIN, "sweep", "slow.lua", "--grid", "f=0.01,0.02", "-j", "2", "--out", "s",
              "--timeout", "300", "--no-cache", nullptr);
      ::_exit(127);
    }
    std::vector<pid_t> runs;
    for (int k = 0; k < 600 && runs.size() < 2; ++k) {  // both runs started (up to a minute)
      std::this_thread::sleep_for(std::chrono::milliseconds(100));
      runs = children_of(sweep);
    }
    INFO(slurp(root / "sweep.log"));
    REQUIRE(runs.size() == 2);
    ::kill(-sweep, SIGKILL);
    int st = 0;
    ::waitpid(sweep, &st, 0);
    bool gone = false;
    for (int k = 0; k < 100 && !gone; ++k) {
      std::this_thread::sleep_for(std::chrono::milliseconds(100));
      gone = !alive(runs[0]) && !alive(runs[1]);
    }
    CHECK(gone);
    for (pid_t p : runs)
      if (alive(p)) ::kill(p, SIGKILL);  // leave nothing behind when the check failed
  }

  // 6. Under a file-size limit softcut died of SIGXFSZ, leaving temporary files.
  TEST_CASE("item 6: under ulimit -f a run fails as on a full disk (no SIGXFSZ death), leaving no temporary files") {
    const fs::path root = softcut::test::scratch_dir("cmd_esc_fsize");
    put_file(root / "s.lua", bar("fsize", "", "3", "30"));  // a ~100 kB log
    // No `trap '' XFSZ` here: softcut itself must not die of the signal.
    const auto r = run_softcut("run --quiet --no-render --out out s.lua", root,
                               "export SOFTCUT_CACHE_DIR=" + (root / "cache").string() + "; ulimit -f 32;");
    INFO(r.output);
    CHECK(r.status == 1);
    CHECK(contains(r.output, "disk full"));
    CHECK(!fs::exists(root / "out" / "displacements.csv"));
    CHECK(count_files(root, ".tmp") == 0);
    CHECK(count_files(root, ".partial") == 0);
    // The run's own summary says why (it was not written before: the log's
    // failed finish ended the run's outputs).
    const auto own = softcut::test::read_json(root / "out" / "summary.json");
    CHECK(own["run"]["exit_reason"] == "error");
    CHECK(contains(own["run"]["message"].get<std::string>(), "failed (disk full?)"));
    // A sweep's run: the same, and the run's summary (written by the sweep) says so.
    const auto sweep = run_softcut("sweep s.lua --grid f=0.01 --no-render --out sw", root,
                                   "export SOFTCUT_CACHE_DIR=" + (root / "cache").string() + "; ulimit -f 32;");
    INFO(sweep.output);
    CHECK(sweep.status == 1);
    CHECK(contains(sweep.output, "FAIL  run_0000  f=0.01: outputs: writing "));
    const auto summary = softcut::test::read_json(root / "sw" / "run_0000" / "summary.json");
    CHECK(summary["run"]["exit_reason"] == "error");
    CHECK(contains(summary["run"]["message"].get<std::string>(), "failed (disk full?)"));
    CHECK(count_files(root, ".tmp") == 0);
    CHECK(count_files(root, ".partial") == 0);
    const auto check = run_softcut("check --record --out out2 --json report.json s.lua", root, "ulimit -f 32;");
    CHECK(check.status == 1);
    CHECK(contains(check.output, "disk full"));
    CHECK(count_files(root, ".tmp") == 0);
  }

  // 12. 100k failing expectations: 1.16 GB RSS, a 228 MB summary, 207 MB on stderr.
  TEST_CASE("item 12: many failing expectations with long messages: bounded count, output and reports") {
    const fs::path root = softcut::test::scratch_dir("cmd_esc_expect");
    put_file(root / "many.lua", bar("many", "for k = 1, 10001 do s:expect{ name = 'e' .. k, at = 0.2, "
                                            "check = function() return true end } end"));
    const auto many = run_softcut("check many.lua", root);
    CHECK(many.status == 1);
    CHECK(contains(many.output, "the scenario declares 10001 expectations, more than 10000"));
    put_file(root / "long.lua", bar("long", "for k = 1, 5000 do s:expect{ name = 'e' .. k, at = 0.2, "
                                            "check = function() return false, ('x'):rep(20000) end } end"));
    const auto r = exec_softcut({"check", "--out", "out", "--junit", "j.xml", "--json", "j.json", "long.lua"}, root, 300);
    CHECK(r.status == 1);
    CHECK(r.output.size() < 100000);  // 100 MB before
    CHECK(contains(r.output, "... and 4981 more failed expectations"));
    CHECK(fs::file_size(root / "out" / "long" / "summary.json") < (16u << 20));
    CHECK(fs::file_size(root / "j.xml") < (1u << 20));
    CHECK(fs::file_size(root / "j.json") < (1u << 20));
    const auto j = softcut::test::read_json(root / "j.json");
    CHECK(j["scenarios"][0]["expectations_total"] == 5000);
    CHECK(j["scenarios"][0]["expectations_failed"] == 5000);
    CHECK(j["scenarios"][0]["expectations_omitted"] == 4900);
    CHECK(r.peak_rss < (1ll << 30));
    // --max-output bounds the reports too.
    const auto small = run_softcut("check --max-output 100K --junit j2.xml long.lua", root);
    CHECK(contains(small.output, "j2.xml: the JUnit report would be"));
  }

  // 14. check --junit wrote XML that is not well-formed.
  TEST_CASE("item 14: JUnit XML stays well-formed and valid with non-UTF-8 names and noncharacters") {
    const fs::path root = softcut::test::scratch_dir("cmd_esc_junit");
    // Names set after softcut.scenario{} (which checks them) reach the engine's own check.
    put_file(root / "weird.lua", bar("weird", "s.name = 'we\xff" "ird'\n"
                                              "s:expect{ name = 'a\xEF\xBF\xBE" "b\\0c', at = 0.2, "
                                              "check = function() return false, 'ctl\\1\\27[31m \xC3\x28' end }"));
    put_file(root / "ctl.lua", bar("ctl", "s.name = 'ctl\\1name'"));  // refused: reported under that name
    put_file(root / "f\xfe.lua", bar("other"));
    const auto r = run_softcut("check --junit report.xml --json report.json .", root);
    INFO(r.output);
    CHECK(r.status == 1);
    const auto lint = softcut::test::run_cli_raw("xmllint --noout --schema '" +
                                                 softcut::test::source("tests/data/junit.xsd") + "' '" +
                                                 (root / "report.xml").string() + "'");
    INFO(lint.output);
    CHECK(lint.status == 0);
    const std::string x = slurp(root / "report.xml");
    CHECK(contains(x, "name=\"we\\xFFird\""));
    CHECK(contains(x, "name=\"ctl\\x01name\""));
    CHECK(contains(x, "a\\u{FFFE}b\\x00c"));
    CHECK(contains(x, "f\\xFE.lua"));
    softcut::test::read_json(root / "report.json");  // valid JSON too
  }
}
