// softcut check PATH... [-j N] [--only PAT] [--exclude PAT] [--timeout S] [--set k=v] [--junit F] [--json F] ...
// Runs each scenario, evaluates its expectations, compares its displacement
// log with the reference next to it; one line per scenario (in file order,
// whatever -j), then "N passed, N failed[, N skipped]"; exit 1 on any failure.
//
// The scenarios may come from a package someone else prepared: a scenario
// found in a folder that is a link (or not a regular file) is not run, every
// scenario and reference is read without following a link at or below the
// folder given, a scenario's name is checked before its folder is made (once,
// below the output root, without following a link), and the default output
// root is a fresh private folder (mkdtemp). docs/hardening.md.
#include <fnmatch.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <cerrno>
#include <chrono>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <map>
#include <mutex>
#include <optional>
#include <thread>

#include "app/check_report.hpp"
#include "app/commands.hpp"
#include "app/option_values.hpp"
#include "app/options.hpp"
#include "app/reference_log.hpp"
#include "app/run_options.hpp"
#include "app/run_support.hpp"
#include "app/scenario_run.hpp"
#include "core/atomic_file.hpp"
#include "core/checked_file.hpp"
#include "core/error.hpp"
#include "core/printable.hpp"
#include "core/threads.hpp"
#include "core/watchdog.hpp"

namespace fs = std::filesystem;

namespace softcut::app {

namespace {

const char* kCheckAbout =
    "Runs each scenario (PATH: a .lua file, or a folder searched for *.lua), evaluates its\n"
    "s:expect{...} checks and compares its displacements.csv with the reference log next to it\n"
    "(<file stem>.ref.csv, tolerance from softcut.scenario{ tolerance = ... }). Files that make no\n"
    "scenario (helper modules) are skipped and listed as such; a *.lua found in a folder that is\n"
    "a symbolic link or not a regular file is not run (it fails, named).";

const char* kCheckFooter =
    "Prints one line per scenario and closes with 'N passed, N failed'. Exit status: 0 all passed,\n"
    "1 a scenario failed, 2 usage error (bad option, no scenario, two scenarios with one name).";

// Most scenario files one check takes, and folder entries it looks at to find them.
constexpr std::size_t kMaxScenarios = 10000;
constexpr std::size_t kMaxEntries = 1000000;
constexpr int kMaxDepth = 32;  // folders below a PATH (deeper: a usage error, never skipped silently)

// A scenario file and where it is read from: `root` is the folder the user
// named (or a named file's folder), `rel` the file below it, read without
// following any link (the reference beside it too).
struct Found {
  fs::path file, root, rel;
  std::string refused;  // why it is not run: a link, not a regular file
};

std::vector<Found> collect(const std::vector<std::string>& paths) {
  std::vector<Found> out;
  auto add = [&](Found f) {
    if (out.size() >= kMaxScenarios)
      usage_fail("softcut check: more than ", kMaxScenarios, " scenario files; check fewer folders at once");
    out.push_back(std::move(f));
  };
  for (const auto& p : paths) {
    std::error_code ec;
    if (fs::is_directory(p, ec)) {
      std::vector<Found> found;
      std::size_t entries = 0;
      // Links to folders are not entered; links to files are listed, not run.
      fs::recursive_directory_iterator it(p, fs::directory_options::none, ec), end;
      if (ec) usage_fail("softcut check: ", printable(p), ": cannot list the folder (", ec.message(), ")");
      for (; it != end; it.increment(ec)) {
        if (ec) usage_fail("softcut check: ", printable(p), ": cannot list the folder (", ec.message(), ")");
        if (++entries > kMaxEntries)
          usage_fail("softcut check: ", printable(p), " holds more than ", kMaxEntries, " entries; name the folders "
                     "of the scenarios");
        if (it.depth() >= kMaxDepth && it->is_directory(ec) && !it->is_symlink(ec))
          usage_fail("softcut check: ", printable(p), " has folders nested more than ", kMaxDepth, " deep (",
                     printable(it->path().string()), "); name the folders of the scenarios");
        if (it->path().extension() != ".lua") continue;
        const fs::file_status st = it->symlink_status(ec);
        if (fs::is_directory(st)) continue;  // a folder named x.lua: searched, not run
        Found f{it->path(), p, it->path().lexically_relative(p), ""};
        if (fs::is_symlink(st))
          f.refused = "is a symbolic link; softcut check runs no linked scenario (copy the file into the folder)";
        else if (!fs::is_regular_file(st))
          f.refused = "is not a regular file (a FIFO, socket or device named *.lua)";
        found.push_back(std::move(f));
      }
      if (found.empty()) usage_fail("softcut check: no *.lua scenario under ", printable(p));
      std::sort(found.begin(), found.end(), [](const Found& a, const Found& b) { return a.file < b.file; });
      for (auto& f : found) add(std::move(f));
    } else if (fs::is_regular_file(p, ec)) {
      const fs::path file(p);
      Found f{file, file.has_parent_path() ? file.parent_path() : fs::path("."), file.filename(), ""};
      if (fs::is_symlink(fs::symlink_status(file, ec)))
        f.refused = "is a symbolic link; softcut check runs no linked scenario (name the file it points to)";
      add(std::move(f));
    } else {
      usage_fail("softcut check: ", printable(p), ": no such file or folder");
    }
  }
  return out;
}

std::string first_line(const std::string& s) { return s.substr(0, s.find('\n')); }

// A scenario's warnings under its verdict line (the first kKeptFailures).
void print_warnings(const CheckedScenario& r) {
  for (const std::string& w : r.warnings) std::printf("      warning: %s\n", printable(first_line(w), 1000).c_str());
  if (r.warnings_total > r.warnings.size())
    std::printf("      ... and %zu more warnings\n", r.warnings_total - r.warnings.size());
}

bool matches(const std::vector<std::string>& globs, const CheckedScenario& r) {
  for (const auto& g : globs)
    if (fnmatch(g.c_str(), r.name.c_str(), 0) == 0 || fnmatch(g.c_str(), r.file.stem().c_str(), 0) == 0) return true;
  return false;
}

// The output root: --out as given (made if missing), else a fresh private
// folder (mkdtemp: mode 0700, a name no other user can predict or plant),
// removed however check ends.
struct OutputRoot {
  fs::path path;
  bool temporary = false;
  explicit OutputRoot(const std::string& out) {
    std::error_code ec;
    if (!out.empty()) {
      path = out;
      fs::create_directories(path, ec);
      if (ec || !fs::is_directory(path, ec))
        fail("softcut check: cannot create the output folder ", printable(out), " (",
             ec ? ec.message() : "not a folder", "); choose another with --out");
      return;
    }
    const fs::path tmp = fs::temp_directory_path(ec);
    std::string name = ((ec ? fs::path("/tmp") : tmp) / "softcut-check-XXXXXX").string();
    if (!::mkdtemp(name.data()))
      fail("softcut check: cannot make a temporary folder ", printable(name), " (", std::strerror(errno),
           "); set TMPDIR or give --out DIR");
    path = name;
    temporary = true;
  }
  ~OutputRoot() {
    std::error_code ec;
    if (temporary) fs::remove_all(path, ec);
  }
  OutputRoot(const OutputRoot&) = delete;
  OutputRoot& operator=(const OutputRoot&) = delete;
};

struct CheckFlags {
  bool record = false, force = false;
};

// Runs one scenario into `r` (status, reason, failures, expectations,
// comparison). Any error is a failure of this scenario only.
void check_one(CheckedScenario& r, const Found& found, const CheckFlags& flags, const fs::path& out_root,
               app::RunRequest req) {
  const auto t0 = std::chrono::steady_clock::now();
  req.scenario = found.file;
  req.scenario_root = found.root;
  req.render = false;
  req.interrupt = &SignalGuard::flag();
  auto failed = [&](const std::string& why) {
    r.status = CheckedScenario::Status::fail;
    if (r.reason.empty()) r.reason = first_line(why);
    r.failures.push_back(why);
  };
  try {
    // The name was checked in pass 1: one plain folder name, made below the
    // root without following a link planted in its place.
    req.out_dir = make_folder_below(out_root, r.name, "softcut check");
    app::RunOutcome out = app::run_scenario(req);
    r.expectations_total = out.expectations.size();
    for (const auto& e : out.expectations) {
      r.expectations_failed += !e.ok;
      if (r.expectations.size() < kKeptExpectations)
        r.expectations.push_back({e.name, e.where, e.reached, e.ok, e.message});
    }
    if (out.result.reason == sim::ExitReason::interrupted) return failed("interrupted");
    if (out.result.reason == sim::ExitReason::error) return failed(out.result.message);
    if (out.result.reason == sim::ExitReason::timeout)
      return failed(cat("the wall-clock limit of ", req.timeout_s, " s (--timeout) passed at frame ",
                        out.result.frames, " of ", out.num_frames));
    // The first failed expectations, then a count: a script may declare
    // thousands, each with a long message.
    for (const auto& e : out.expectations) {
      if (e.ok) continue;
      if (r.failures.size() + 1 < kKeptFailures) failed(cat(e.where, ": expect '", e.name, "' failed: ", e.message));
      else ++r.failures_omitted;
    }
    if (r.failures_omitted) r.failures.push_back(cat("... and ", r.failures_omitted, " more failed expectations"));
    r.warnings_total = out.warnings.size();
    for (size_t k = 0; k < out.warnings.size() && k < kKeptFailures; ++k) r.warnings.push_back(out.warnings[k]);
    if (req.warnings_as_errors && !out.warnings.empty()) {  // fails as a failed expectation does: nothing recorded
      r.warnings_failed = true;
      failed(warned_message(out.warnings));
      for (size_t k = 1; k < r.warnings.size(); ++k) failed(cat("warning: ", r.warnings[k]));
      if (out.warnings.size() > r.warnings.size())
        failed(cat("... and ", out.warnings.size() - r.warnings.size(), " more warnings"));
    }
    const bool expectations_failed = !r.failures.empty();

    // The log comparison also when an expectation failed: both are reported.
    // It counts against the scenario's --timeout too.
    const double spent = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    const Watchdog dog(req.timeout_s > 0 ? std::max(1e-3, req.timeout_s - spent) : 0,
                       std::clamp(req.timeout_s / 10, 5.0, 60.0),
                       cat(found.file.string(), ": the wall-clock limit of ", req.timeout_s,
                           " s (--timeout) passed while reading its reference log, which did not end; exiting"));
    CompareLimits limits;
    limits.timeout = &dog.expired();
    limits.timeout_s = req.timeout_s;
    limits.interrupt = req.interrupt;
    const LogFile log{out.out_dir, "displacements.csv"};
    const LogFile ref{found.root, reference_path(found.rel)};
    const std::string how = cat("record one with `softcut check --record ", r.file.string(), "`");
    std::error_code ec;
    if (!fs::exists(fs::symlink_status(out.out_dir / "displacements.csv", ec)))
      return failed("the run wrote no displacements.csv (s:output{ csv = false }?)");
    const RunIdentity who{out.name, out.mesh_fingerprint, out.params};
    const int n_expect = int(out.expectations.size());
    const bool ref_exists = fs::exists(fs::symlink_status(found.root / ref.rel, ec));
    if (flags.record) {
      if (expectations_failed) return;  // a failing scenario records nothing
      if (ref_exists && !flags.force) {
        // A reference another scenario made is never overwritten silently.
        const ReferenceHeader old = read_reference_header(ref);
        if (old.present && old.scenario != out.name)
          return failed(cat(ref.shown(), " was recorded by scenario '", printable(old.scenario, 100), "', not '",
                            printable(out.name, 100), "'; --record would overwrite another scenario's reference: "
                            "move it away, or give --force"));
      }
      ReferenceHeader h;
      h.scenario = out.name, h.mesh = out.mesh_fingerprint, h.params = out.params, h.softcut = SOFTCUT_VERSION;
      write_file_atomic(found.root / ref.rel, [&](std::ostream& os) { copy_as_reference(log, h, os, limits); });
      r.detail = cat("recorded ", ref.shown(), " (", out.result.frames, " frames, ", n_expect, " expectations)");
      r.status = CheckedScenario::Status::pass;
      return;
    }
    if (!ref_exists) return failed(cat("no reference log ", ref.shown(), "; ", how));
    const LogComparison c = compare_logs(log, ref, out.tolerance, &who, limits);  // throws on a corrupt reference
    if (c.foreign)
      return failed(cat(c.message, " (", ref.shown(), "); put this scenario's own reference there, or ", how,
                        " --force"));
    r.compared = true;
    r.max_diff = c.max_diff, r.scale = c.scale, r.tolerance = out.tolerance;
    r.worst_frame = c.worst_frame, r.worst_node = c.worst_node;
    if (c.stale) return failed(cat("stale reference ", ref.shown(), ": ", c.message, "; re-", how));
    if (!c.ok) return failed(cat(c.message, " (", ref.shown(), "); if the change is intended, re-", how));
    if (expectations_failed) return;
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
  std::vector<std::string> paths, only, exclude;
  std::string out, junit_text, json_text;
  int jobs = 0;
  CheckFlags flags;
  app.add_option("path", paths, "scenario files, or folders searched for *.lua")->type_name("PATH...");
  CLI::Option* jobs_opt = app.add_option("-j,--jobs", jobs, "scenarios run at once (default: the machine's cores)")
                              ->type_name("N")->check(whole_number(1, 100000));
  o.add_list("--only", only, "run only scenarios whose name or file stem matches the glob PAT (repeatable)")
      ->type_name("PAT");
  o.add_list("--exclude", exclude, "leave out scenarios whose name or file stem matches PAT (repeatable)")
      ->type_name("PAT");
  RunOptions run(o, RunOptions::scenario);
  app.add_option("--junit", junit_text, "write a JUnit XML report (one testcase per scenario, expectations as "
                 "assertions)")->type_name("FILE");
  app.add_option("--json", json_text, "write a JSON report (docs/outputs.md, \"softcut check\")")->type_name("FILE");
  app.add_flag("--record", flags.record, "(re)write the reference logs of the scenarios whose expectations pass");
  app.add_flag("--force", flags.force, "with --record: also overwrite a reference another scenario recorded");
  app.add_option("--out", out, "keep the outputs under DIR/<scenario name>/ (default: a temporary folder, removed)")
      ->type_name("DIR");
  for (const auto& [option, what] : {std::pair{"--jobs", "a number"}, {"--only", "a name or glob"},
                                     {"--exclude", "a name or glob"}, {"--junit", "a file"}, {"--json", "a file"},
                                     {"--out", "a folder"}})
    o.needs(option, what);
  if (args.empty()) {
    std::fputs(o.help().c_str(), stderr);
    return 2;
  }
  if (!o.parse(args)) return 0;
  app::RunRequest base;
  run.apply(base);
  base.command_line = {"softcut", "check"};
  base.command_line.insert(base.command_line.end(), args.begin(), args.end());
  if (!jobs_opt->count()) jobs = std::max(1, int(std::thread::hardware_concurrency()));
  const fs::path junit = junit_text, json = json_text;
  if (paths.empty()) usage_fail("softcut check: give a scenario file or folder (see softcut check --help)");
  const auto t0 = std::chrono::steady_clock::now();
  const SignalGuard signals;

  // Pass 1: every file's script part (names for folders, filters and the
  // duplicate check; helper modules make no scenario and are skipped), each
  // within --timeout and Ctrl-C.
  const std::vector<Found> found_all = collect(paths);
  std::vector<CheckedScenario> all;
  std::vector<const Found*> found;  // of each entry of `all`
  std::vector<char> runnable;       // the script made a scenario with a usable name: run it in pass 2
  for (const Found& f : found_all) {
    CheckedScenario r;
    r.file = f.file;
    r.name = f.file.stem().string();
    bool run_it = false;
    if (!f.refused.empty()) {
      r.reason = cat(printable(f.file.string()), " ", f.refused);
      r.failures.push_back(r.reason);
    } else {
      app::RunRequest req = base;
      req.scenario = f.file;
      req.scenario_root = f.root;
      req.interrupt = &SignalGuard::flag();
      try {
        const Watchdog dog(req.timeout_s, std::clamp(req.timeout_s / 10, 5.0, 60.0),
                           cat(f.file.string(), ": the wall-clock limit of ", req.timeout_s, " s (--timeout) passed "
                               "while the script ran and it did not stop; exiting"));
        const sim::ScenarioSpec spec = app::load_scenario_spec(
            req, [&dog](const RunRequest& q, OutputBudget* output, const Watchdog*) {
              return open_lua_scenario(q, output, &dog);
            });
        r.name = spec.name;
        if (dog.expired().load()) fail("the wall-clock limit of ", req.timeout_s, " s (--timeout) passed");
        // The name (and everything else checkable without the mesh) is
        // checked before any folder is made or cleared for it.
        try {
          sim::check_spec(spec);
        } catch (const Error& e) {
          const std::string msg = e.what();
          if (msg.rfind(f.file.string(), 0) == 0) throw;
          fail(f.file.string(), ": ", msg);
        }
        run_it = true;
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
    }
    if (!only.empty() && !matches(only, r)) continue;
    if (matches(exclude, r)) continue;
    all.push_back(std::move(r));
    found.push_back(&f);
    runnable.push_back(run_it);
  }
  if (all.empty()) usage_fail("softcut check: no scenario left after --only/--exclude");
  std::map<std::string, fs::path> by_name;
  for (size_t i = 0; i < all.size(); ++i) {
    const CheckedScenario& r = all[i];
    if (!runnable[i]) continue;
    const auto [it, fresh] = by_name.emplace(r.name, r.file);
    if (!fresh)
      usage_fail("softcut check: two scenarios are named '", printable(r.name), "': ", it->second.string(), " and ",
                 r.file.string(), "; their outputs would share a folder. Give one a different "
                 "softcut.scenario{ name = ... }");
  }

  // Pass 2: the runs, `jobs` at once; lines print in file order as soon as
  // every earlier scenario is done.
  const OutputRoot out_root(out);
  std::vector<char> done(all.size(), 0);
  std::atomic<size_t> next{0};
  std::mutex mutex;
  size_t printed = 0;
  int passed = 0, failed = 0, skipped = 0;
  auto print_ready = [&] {  // under `mutex`
    for (; printed < all.size() && done[printed]; ++printed) {
      const CheckedScenario& r = all[printed];
      const std::string file = printable(r.file.string(), 400);
      if (r.status == CheckedScenario::Status::pass) {
        ++passed;
        std::printf("PASS  %s  (%s)\n", file.c_str(), r.detail.c_str());
        print_warnings(r);
      } else if (r.status == CheckedScenario::Status::skipped) {
        ++skipped;
        std::printf("SKIP  %s: %s\n", file.c_str(), printable(r.reason, 400).c_str());
      } else {
        ++failed;
        std::printf("FAIL  %s: %s\n", file.c_str(), printable(r.reason, 1000).c_str());
        for (size_t k = 1; k < r.failures.size(); ++k)
          std::printf("      %s\n", printable(first_line(r.failures[k]), 1000).c_str());
        if (!r.warnings_failed) print_warnings(r);
      }
    }
    std::fflush(stdout);
  };
  auto worker = [&] {
    for (size_t i; (i = next++) < all.size();) {
      CheckedScenario& r = all[i];
      if (runnable[i] && !SignalGuard::flag().load()) {
        const auto s0 = std::chrono::steady_clock::now();
        check_one(r, *found[i], flags, out_root.path, base);
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
  if (!junit.empty()) write_junit(junit, all, total_s, base.max_output);
  if (!json.empty()) write_check_json(json, all, total_s, base.max_output);
  if (skipped) std::printf("%d passed, %d failed, %d skipped\n", passed, failed, skipped);
  else std::printf("%d passed, %d failed\n", passed, failed);
  return failed ? 1 : 0;
}

}  // namespace softcut::app
