// softcut check PATH... [--record] [--out DIR] [--backend B] [--max-tets N] [--trust]
// Runs each scenario, evaluates its expectations, compares its displacement
// log with the reference next to it; one line per scenario, then
// "N passed, N failed"; exit 1 on any failure.
#include <unistd.h>

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "cli/commands.hpp"
#include "hybrid/precompute_cache.hpp"
#include "cli/reference_log.hpp"
#include "cli/run_support.hpp"
#include "core/atomic_file.hpp"
#include "core/error.hpp"
#include "scenario_runner.hpp"

namespace fs = std::filesystem;

namespace softcut::cli {

namespace {

const char* kCheckUsage =
    "usage: softcut check PATH... [--record] [--out DIR] [--backend B] [--max-tets N] [--trust] [--no-cache]\n"
    "\n"
    "Runs each scenario (PATH: a .lua file, or a folder searched for *.lua), evaluates its\n"
    "s:expect{...} checks and compares its displacements.csv with the reference log next to it\n"
    "(<name>.ref.csv, tolerance from softcut.scenario{ tolerance = ... }).\n"
    "  --record   (re)write the reference logs of the scenarios whose expectations pass\n"
    "  --out DIR  keep the outputs under DIR/<scenario name>/ (default: a temporary folder)\n"
    "  --backend B  operational solver for every scenario: auto, cpu, gpu, direct or monolithic\n"
    "  --max-tets N  sandbox: largest mesh a scenario may load or generate (default 2000000 tets)\n"
    "  --trust    no sandbox\n"
    "  --no-cache  redo every hybrid precompute instead of loading it from the cache\n"
    "Prints one line per scenario and closes with 'N passed, N failed'; exit status 1 on any failure.\n";

std::vector<fs::path> collect(const std::vector<std::string>& paths) {
  std::vector<fs::path> out;
  for (const auto& p : paths) {
    if (fs::is_directory(p)) {
      std::vector<fs::path> found;
      for (const auto& e : fs::recursive_directory_iterator(p))
        if (e.is_regular_file() && e.path().extension() == ".lua") found.push_back(e.path());
      if (found.empty()) fail("softcut check: no *.lua scenario under ", p);
      std::sort(found.begin(), found.end());
      out.insert(out.end(), found.begin(), found.end());
    } else if (fs::is_regular_file(p)) {
      out.emplace_back(p);
    } else {
      fail("softcut check: ", p, ": no such file or folder");
    }
  }
  return out;
}

std::string first_line(const std::string& s) { return s.substr(0, s.find('\n')); }

// One scenario -> "" (pass) or the failure reason; `detail` gets the pass note.
// `req` carries the options shared by every scenario (sandbox, backend).
std::string check_one(const fs::path& scenario, bool record, const fs::path& out_root, lua::RunRequest req,
                      std::string& detail) {
  req.scenario = scenario;
  req.render = false;
  req.interrupt = &SignalGuard::flag();
  req.out_dir = out_root / scenario.stem();
  lua::RunOutcome out;
  try {
    out = lua::run_scenario(req);
  } catch (const Error& e) {
    const std::string msg = e.what();
    if (msg.find('\n') != std::string::npos) std::fprintf(stderr, "%s\n", msg.c_str());
    return first_line(msg);
  }
  if (out.result.reason == sim::ExitReason::interrupted) return "interrupted";
  if (out.result.reason == sim::ExitReason::error) return out.result.message;
  int passed = 0;
  for (const auto& e : out.expectations) {
    if (!e.ok) return cat(e.where, ": expect '", e.name, "' failed: ", e.message);
    ++passed;
  }
  const fs::path log = out.out_dir / "displacements.csv";
  const fs::path ref = reference_path(scenario);
  const std::string how = cat("record one with `softcut check --record ", scenario.string(), "`");
  if (!fs::exists(log)) return "the run wrote no displacements.csv (s:output{ csv = false }?)";
  if (record) {
    std::ifstream in(log, std::ios::binary);
    std::stringstream ss;
    ss << in.rdbuf();
    write_file_atomic(ref, ss.str());
    detail = cat("recorded ", ref.string(), " (", out.result.frames, " frames, ", passed, " expectations)");
    return "";
  }
  if (!fs::exists(ref)) return cat("no reference log ", ref.string(), "; ", how);
  const LogComparison c = compare_logs(log, ref, out.tolerance);
  if (c.stale) return cat("stale reference ", ref.string(), ": ", c.message, "; re-", how);
  if (!c.ok)
    return cat(c.message, " (", ref.string(), "); if the change is intended, re-", how);
  char buf[160];
  std::snprintf(buf, sizeof buf, "%d frames, %d expectations, max |du| %.2g m (scale %.3g m), %.2f s", out.result.frames,
                passed, c.max_diff, c.scale, out.result.wall_s);
  detail = buf;
  return "";
}

}  // namespace

int cmd_check(const Args& args) {
  if (args.empty() || args[0] == "--help" || args[0] == "-h") {
    std::fputs(kCheckUsage, args.empty() ? stderr : stdout);
    return args.empty() ? 2 : 0;
  }
  bool record = false;
  lua::RunRequest base;
  base.cache_dir = hybrid::default_cache_dir();
  fs::path out_root;
  std::vector<std::string> paths;
  for (size_t i = 0; i < args.size(); ++i) {
    const std::string& a = args[i];
    if (a == "--record") record = true;
    else if (a == "--trust") base.trusted = true;
    else if (a == "--no-cache") base.cache_dir.clear();
    else if (a == "--backend") {
      if (i + 1 >= args.size()) usage_fail("softcut check: --backend needs a value");
      base.backend = parse_backend(args[++i]);
    } else if (a == "--max-tets") {
      if (i + 1 >= args.size()) usage_fail("softcut check: --max-tets needs a number");
      base.max_tets = parse_count(args[++i], "--max-tets");
    }
    else if (a == "--out") {
      if (i + 1 >= args.size()) usage_fail("softcut check: --out needs a folder");
      out_root = args[++i];
    } else if (a.rfind("-", 0) == 0) usage_fail("softcut check: unknown option '", a, "' (see softcut check --help)");
    else paths.push_back(a);
  }
  const std::vector<fs::path> scenarios = collect(paths);
  const bool temp = out_root.empty();
  if (temp) out_root = fs::temp_directory_path() / cat("softcut-check-", ::getpid());
  const SignalGuard signals;
  int passed = 0, failed = 0;
  for (const fs::path& s : scenarios) {
    std::string detail;
    const std::string why = check_one(s, record, out_root, base, detail);
    if (why.empty()) {
      ++passed;
      std::printf("PASS  %s  (%s)\n", s.string().c_str(), detail.c_str());
    } else {
      ++failed;
      std::printf("FAIL  %s: %s\n", s.string().c_str(), why.c_str());
    }
    std::fflush(stdout);
    if (SignalGuard::flag().load()) break;
  }
  if (temp) {
    std::error_code ec;
    fs::remove_all(out_root, ec);
  }
  std::printf("%d passed, %d failed\n", passed, failed);
  return failed ? 1 : 0;
}

}  // namespace softcut::cli
