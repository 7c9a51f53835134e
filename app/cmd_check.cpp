// softcut check PATH... [-j N] [--only PAT] [--exclude PAT] [--timeout S] [--set k=v] [--junit F] [--json F] ...
// Runs each scenario, evaluates its expectations, compares its displacement
// log with the reference next to it; one line per scenario (in file order,
// whatever -j), then "N passed, N failed[, N skipped]"; exit 1 on any failure.
#include <fnmatch.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <map>
#include <mutex>
#include <optional>
#include <sstream>
#include <thread>

#include "app/check_report.hpp"
#include "app/commands.hpp"
#include "app/options.hpp"
#include "app/reference_log.hpp"
#include "app/run_support.hpp"
#include "core/atomic_file.hpp"
#include "core/error.hpp"
#include "core/threads.hpp"
#include "hybrid/precompute_cache.hpp"
#include "app/scenario_run.hpp"

namespace fs = std::filesystem;

namespace softcut::app {

namespace {

const char* kCheckAbout =
    "Runs each scenario (PATH: a .lua file, or a folder searched for *.lua), evaluates its\n"
    "s:expect{...} checks and compares its displacements.csv with the reference log next to it\n"
    "(<file stem>.ref.csv, tolerance from softcut.scenario{ tolerance = ... }). Files that make no\n"
    "scenario (helper modules) are skipped and listed as such.";

const char* kCheckFooter =
    "Prints one line per scenario and closes with 'N passed, N failed'. Exit status: 0 all passed,\n"
    "1 a scenario failed, 2 usage error (bad option, no scenario, two scenarios with one name).";

std::vector<fs::path> collect(const std::vector<std::string>& paths) {
  std::vector<fs::path> out;
  for (const auto& p : paths) {
    if (fs::is_directory(p)) {
      std::vector<fs::path> found;
      for (const auto& e : fs::recursive_directory_iterator(p))
        if (e.is_regular_file() && e.path().extension() == ".lua") found.push_back(e.path());
      if (found.empty()) usage_fail("softcut check: no *.lua scenario under ", p);
      std::sort(found.begin(), found.end());
      out.insert(out.end(), found.begin(), found.end());
    } else if (fs::is_regular_file(p)) {
      out.emplace_back(p);
    } else {
      usage_fail("softcut check: ", p, ": no such file or folder");
    }
  }
  return out;
}

std::string first_line(const std::string& s) { return s.substr(0, s.find('\n')); }

bool matches(const std::vector<std::string>& globs, const CheckedScenario& r) {
  for (const auto& g : globs)
    if (fnmatch(g.c_str(), r.name.c_str(), 0) == 0 || fnmatch(g.c_str(), r.file.stem().c_str(), 0) == 0) return true;
  return false;
}

// The temporary output root, removed however check ends.
struct TempRoot {
  fs::path path;
  ~TempRoot() {
    std::error_code ec;
    if (!path.empty()) fs::remove_all(path, ec);
  }
};

// Runs one scenario into `r` (status, reason, failures, expectations,
// comparison). Any error is a failure of this scenario only.
void check_one(CheckedScenario& r, bool record, const fs::path& out_root, app::RunRequest req) {
  req.scenario = r.file;
  req.render = false;
  req.interrupt = &SignalGuard::flag();
  req.out_dir = out_root / r.name;
  auto failed = [&](const std::string& why) {
    r.status = CheckedScenario::Status::fail;
    if (r.reason.empty()) r.reason = first_line(why);
    r.failures.push_back(why);
  };
  try {
    app::RunOutcome out = app::run_scenario(req);
    for (const auto& e : out.expectations) r.expectations.push_back({e.name, e.where, e.reached, e.ok, e.message});
    if (out.result.reason == sim::ExitReason::interrupted) return failed("interrupted");
    if (out.result.reason == sim::ExitReason::error) return failed(out.result.message);
    if (out.result.reason == sim::ExitReason::timeout)
      return failed(cat("the wall-clock limit of ", req.timeout_s, " s (--timeout) passed at frame ",
                        out.result.frames, " of ", out.num_frames));
    for (const auto& e : out.expectations)
      if (!e.ok) failed(cat(e.where, ": expect '", e.name, "' failed: ", e.message));
    if (!r.failures.empty()) return;
    const fs::path log = out.out_dir / "displacements.csv";
    const fs::path ref = reference_path(r.file);
    const std::string how = cat("record one with `softcut check --record ", r.file.string(), "`");
    if (!fs::exists(log)) return failed("the run wrote no displacements.csv (s:output{ csv = false }?)");
    const int n_expect = int(out.expectations.size());
    if (record) {
      std::ifstream in(log, std::ios::binary);
      std::stringstream ss;
      ss << in.rdbuf();
      write_file_atomic(ref, ss.str());
      r.detail = cat("recorded ", ref.string(), " (", out.result.frames, " frames, ", n_expect, " expectations)");
      r.status = CheckedScenario::Status::pass;
      return;
    }
    if (!fs::exists(ref)) return failed(cat("no reference log ", ref.string(), "; ", how));
    const LogComparison c = compare_logs(log, ref, out.tolerance);  // throws on a corrupt reference
    r.compared = true;
    r.max_diff = c.max_diff, r.scale = c.scale, r.tolerance = out.tolerance;
    r.worst_frame = c.worst_frame, r.worst_node = c.worst_node;
    if (c.stale) return failed(cat("stale reference ", ref.string(), ": ", c.message, "; re-", how));
    if (!c.ok) return failed(cat(c.message, " (", ref.string(), "); if the change is intended, re-", how));
    char buf[160];
    std::snprintf(buf, sizeof buf, "%d frames, %d expectations, max |du| %.2g m (scale %.3g m), %.2f s",
                  out.result.frames, n_expect, c.max_diff, c.scale, out.result.wall_s);
    r.detail = buf;
    r.status = CheckedScenario::Status::pass;
  } catch (const std::exception& e) {
    failed(e.what());
  }
}

}  // namespace

int cmd_check(const Args& args) {
  Options o("softcut check", kCheckAbout, kCheckFooter);
  CLI::App& app = o.app();
  std::vector<std::string> paths, only, exclude, sets;
  std::string jobs_text, timeout, backend, max_tets, out, junit_text, json_text;
  bool record = false, trust = false, no_cache = false;
  app.add_option("path", paths, "scenario files, or folders searched for *.lua")->type_name("PATH...");
  app.add_option("-j,--jobs", jobs_text, "scenarios run at once (default: the machine's cores)")->type_name("N");
  o.add_list("--only", only, "run only scenarios whose name or file stem matches the glob PAT (repeatable)")
      ->type_name("PAT");
  o.add_list("--exclude", exclude, "leave out scenarios whose name or file stem matches PAT (repeatable)")
      ->type_name("PAT");
  app.add_option("--timeout", timeout, "wall-clock limit per scenario, s (default 3600; 0: none); past it the "
                 "scenario fails")->type_name("S");
  o.add_list("--set", sets, "override a parameter of every scenario (each must declare it in softcut.params)")
      ->type_name("key=value");
  app.add_option("--junit", junit_text, "write a JUnit XML report (one testcase per scenario, expectations as "
                 "assertions)")->type_name("FILE");
  app.add_option("--json", json_text, "write a JSON report (docs/outputs.md, \"softcut check\")")->type_name("FILE");
  app.add_flag("--record", record, "(re)write the reference logs of the scenarios whose expectations pass");
  app.add_option("--out", out, "keep the outputs under DIR/<scenario name>/ (default: a temporary folder, removed)")
      ->type_name("DIR");
  app.add_option("--backend", backend, "operational solver for every scenario: auto, cpu, gpu, direct or monolithic")
      ->type_name("B");
  app.add_option("--max-tets", max_tets, "sandbox: largest mesh a scenario may load or generate (default 2000000 "
                 "tets)")->type_name("N");
  app.add_flag("--trust", trust, "no sandbox");
  app.add_flag("--no-cache", no_cache, "redo every hybrid precompute instead of loading it from the cache");
  for (const auto& [option, what] : {std::pair{"--jobs", "a number"}, {"--only", "a name or glob"},
                                     {"--exclude", "a name or glob"}, {"--timeout", "seconds"}, {"--set", "key=value"},
                                     {"--junit", "a file"}, {"--json", "a file"}, {"--out", "a folder"},
                                     {"--max-tets", "a number"}})
    o.needs(option, what);
  if (args.empty()) {
    std::fputs(o.help().c_str(), stderr);
    return 2;
  }
  if (!o.parse(args)) return 0;
  app::RunRequest base;
  base.cache_dir = no_cache ? fs::path() : hybrid::default_cache_dir();
  base.command_line = {"softcut", "check"};
  base.command_line.insert(base.command_line.end(), args.begin(), args.end());
  base.trusted = trust;
  if (app.count("--backend")) base.backend = parse_backend(backend);
  if (app.count("--max-tets")) base.max_tets = parse_count(max_tets, "--max-tets");
  if (app.count("--timeout")) base.timeout_s = parse_seconds(timeout, "--timeout");
  for (const auto& s : sets) add_override(base.overrides, s);
  const int jobs = app.count("--jobs") ? parse_jobs(jobs_text, "softcut check")
                                       : std::max(1, int(std::thread::hardware_concurrency()));
  fs::path out_root = out;
  const fs::path junit = junit_text, json = json_text;
  if (paths.empty()) usage_fail("softcut check: give a scenario file or folder (see softcut check --help)");
  const auto t0 = std::chrono::steady_clock::now();
  const SignalGuard signals;

  // Pass 1: every file's script part (names for folders, filters and the
  // duplicate check; helper modules make no scenario and are skipped).
  std::vector<CheckedScenario> all;
  std::vector<char> runnable;  // the script made a scenario: run it in pass 2
  for (const fs::path& file : collect(paths)) {
    CheckedScenario r;
    r.file = file;
    r.name = file.stem().string();
    app::RunRequest req = base;
    req.scenario = file;
    bool run = false;
    try {
      r.name = app::load_scenario_spec(req).name;
      run = true;
    } catch (const std::exception& e) {
      const std::string msg = e.what();
      if (msg.find("the script made no scenario") != std::string::npos) {
        r.status = CheckedScenario::Status::skipped;
        r.reason = "makes no scenario (a helper module?)";
      } else {
        r.reason = first_line(msg);
        r.failures.push_back(msg);
      }
    }
    if (!only.empty() && !matches(only, r)) continue;
    if (matches(exclude, r)) continue;
    all.push_back(std::move(r));
    runnable.push_back(run);
  }
  if (all.empty()) usage_fail("softcut check: no scenario left after --only/--exclude");
  std::map<std::string, fs::path> by_name;
  for (size_t i = 0; i < all.size(); ++i) {
    const CheckedScenario& r = all[i];
    if (!runnable[i]) continue;
    const auto [it, fresh] = by_name.emplace(r.name, r.file);
    if (!fresh)
      usage_fail("softcut check: two scenarios are named '", r.name, "': ", it->second.string(), " and ",
                 r.file.string(), "; their outputs would share a folder. Give one a different "
                 "softcut.scenario{ name = ... }");
  }

  // Pass 2: the runs, `jobs` at once; lines print in file order as soon as
  // every earlier scenario is done.
  TempRoot temp;
  if (out_root.empty()) {
    out_root = fs::temp_directory_path() / cat("softcut-check-", ::getpid());
    temp.path = out_root;
  }
  std::vector<char> done(all.size(), 0);
  std::atomic<size_t> next{0};
  std::mutex mutex;
  size_t printed = 0;
  int passed = 0, failed = 0, skipped = 0;
  auto print_ready = [&] {  // under `mutex`
    for (; printed < all.size() && done[printed]; ++printed) {
      const CheckedScenario& r = all[printed];
      if (r.status == CheckedScenario::Status::pass) {
        ++passed;
        std::printf("PASS  %s  (%s)\n", r.file.string().c_str(), r.detail.c_str());
      } else if (r.status == CheckedScenario::Status::skipped) {
        ++skipped;
        std::printf("SKIP  %s: %s\n", r.file.string().c_str(), r.reason.c_str());
      } else {
        ++failed;
        std::printf("FAIL  %s: %s\n", r.file.string().c_str(), r.reason.c_str());
        for (size_t k = 1; k < r.failures.size(); ++k) std::printf("      %s\n", first_line(r.failures[k]).c_str());
      }
    }
    std::fflush(stdout);
  };
  auto worker = [&] {
    for (size_t i; (i = next++) < all.size();) {
      CheckedScenario& r = all[i];
      if (runnable[i] && !SignalGuard::flag().load()) {
        const auto s0 = std::chrono::steady_clock::now();
        check_one(r, record, out_root, base);
        r.time_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - s0).count();
      } else if (runnable[i]) {
        r.reason = "interrupted before it ran";
      }
      std::lock_guard<std::mutex> lock(mutex);
      done[i] = 1;
      print_ready();
    }
  };
  const int n_threads = std::min<int>(jobs, int(all.size()));
  // Runs side by side share the cores: each on one BLAS thread (core/threads.hpp:
  // oversubscribed OpenBLAS threads spin and fight), set before any of them calls BLAS.
  std::optional<SingleThreadedBlas> one_blas_thread;
  if (n_threads > 1) one_blas_thread.emplace();
  std::vector<std::thread> threads;
  for (int k = 1; k < n_threads; ++k) threads.emplace_back(worker);
  worker();
  for (auto& t : threads) t.join();

  const double total_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  if (!junit.empty()) write_junit(junit, all, total_s);
  if (!json.empty()) write_check_json(json, all, total_s);
  if (skipped) std::printf("%d passed, %d failed, %d skipped\n", passed, failed, skipped);
  else std::printf("%d passed, %d failed\n", passed, failed);
  return failed ? 1 : 0;
}

}  // namespace softcut::app
