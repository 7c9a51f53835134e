// softcut sweep SCENARIO.lua (--grid key=v1,v2,... | --table FILE.csv) [-j N] [--shard I/N] ...
// softcut sweep merge DIR
// Expands parameter combinations into runs with stable ids and folders
// (sweep_plan.hpp), runs this shard's slice of them, each as its own
// `softcut run` process (a crash or a blown budget stays with its run, and
// each summary.json records the exact command that reruns it), `-j` at once;
// one line per run in id order, then the tally. `merge` gathers the
// summaries into one table (sweep_merge.hpp). docs/sweeps.md.
#include <fcntl.h>
#include <sched.h>
#include <signal.h>
#include <sys/prctl.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <cerrno>
#include <cstring>
#include <map>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <mutex>
#include <optional>
#include <thread>

#include "app/commands.hpp"
#include "app/json_input.hpp"
#include "app/option_values.hpp"
#include "app/options.hpp"
#include "app/run_options.hpp"
#include "app/run_support.hpp"
#include "app/sweep_merge.hpp"
#include "app/sweep_plan.hpp"
#include "core/atomic_file.hpp"
#include "core/checked_file.hpp"
#include "core/error.hpp"
#include "core/json_text.hpp"
#include "core/printable.hpp"
#include "core/threads.hpp"
#include "core/watchdog.hpp"
#include "app/scenario_run.hpp"
#include "sim/outputs.hpp"

extern char** environ;

namespace fs = std::filesystem;

namespace softcut::app {

namespace {

const char* kSweepAbout =
    "Runs a scenario once per parameter combination. --grid gives a parameter's values (the\n"
    "Cartesian product of all grids, the last varying fastest); --table gives one run per CSV row\n"
    "(a header of parameter names). Each parameter must be declared in the scenario's\n"
    "softcut.params. Run i is DIR/run_000i/ (its outputs, run.log and summary.json); every shard\n"
    "writes the same DIR/sweep_plan.json. Each run is a `softcut run` process with the run options\n"
    "below passed on (see softcut run --help).\n"
    "       softcut sweep merge DIR [--csv FILE] [--json FILE]\n"
    "gathers every run's summary.json into DIR/sweep.csv and DIR/sweep.json (or --csv FILE,\n"
    "--json FILE); it fails naming the runs that have no summary.";

const char* kSweepFooter =
    "--shard I/N runs only the runs i with i % N == I (0 <= I < N), so N machines share a sweep;\n"
    "without it: SLURM_ARRAY_TASK_ID - SLURM_ARRAY_TASK_MIN of SLURM_ARRAY_TASK_COUNT (a Slurm\n"
    "array job), or JOB_COMPLETION_INDEX of --shards N (a Kubernetes indexed Job), else every run.\n"
    "Prints one line per run (PASS/FAIL, id, parameters) and closes with 'N passed, N failed'.\n"
    "Exit status: 0 all passed; 1 a run failed, or the sweep could not start (a bad table, a\n"
    "parameter the scenario does not declare, a folder holding another sweep), or for merge a run\n"
    "failed or is missing; 2 usage error (bad option or grid); 130 interrupted.";

// CPUs this process may run on (Slurm and containers restrict the affinity).
int usable_cores() {
  cpu_set_t set;
  if (sched_getaffinity(0, sizeof set, &set) == 0) return std::max(1, CPU_COUNT(&set));
  return std::max(1, int(std::thread::hardware_concurrency()));
}

std::string params_text(const SweepRun& r) {
  std::string s;
  for (const auto& [k, v] : r.params) s += (s.empty() ? "" : " ") + k + "=" + v;
  return printable(s, 200);
}

// Runs `argv` with stdout and stderr into `log` (made new: an earlier one,
// a link or a hard link is unlinked first, never written through) and stdin
// from /dev/null. The run is in its own process group, so a Ctrl-C at the
// terminal reaches the sweep alone, which passes a stop on once (SignalGuard)
// to each run; and it dies with the sweep (PR_SET_PDEATHSIG: SIGKILL when the
// thread that started it ends, which it does only after waiting for it), so
// killing the sweep (CI cancel, OOM kill, timeout -s KILL) leaves no run
// behind. Returns the wait status.
int spawn_and_wait(const std::vector<std::string>& argv, const fs::path& log, const std::vector<std::string>& env) {
  ::unlink(log.c_str());
  const UniqueFd out(::open(log.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_NOFOLLOW | O_CLOEXEC, 0644));
  if (!out) fail("softcut sweep: cannot create ", log.string(), " (", std::strerror(errno), ")");
  const UniqueFd in(::open("/dev/null", O_RDONLY | O_CLOEXEC));
  if (!in) fail("softcut sweep: cannot open /dev/null (", std::strerror(errno), ")");
  std::vector<char*> cargv, cenv;
  for (const auto& a : argv) cargv.push_back(const_cast<char*>(a.c_str()));
  for (const auto& e : env) cenv.push_back(const_cast<char*>(e.c_str()));
  cargv.push_back(nullptr), cenv.push_back(nullptr);
  const pid_t parent = ::getpid();
  const pid_t pid = ::fork();
  if (pid == 0) {
    // The child of a threaded process: only async-signal-safe calls until exec.
    if (::prctl(PR_SET_PDEATHSIG, SIGKILL) != 0 || ::getppid() != parent) ::_exit(127);  // the sweep already died
    if (::setpgid(0, 0) != 0 || ::dup2(in.get(), STDIN_FILENO) < 0 || ::dup2(out.get(), STDOUT_FILENO) < 0 ||
        ::dup2(out.get(), STDERR_FILENO) < 0)
      ::_exit(127);
    ::execve("/proc/self/exe", cargv.data(), cenv.data());
    ::_exit(127);
  }
  if (pid < 0) fail("softcut sweep: cannot start `softcut run` (", std::strerror(errno), ")");
  int status = 0;
  bool stopped = false;
  for (;;) {
    const pid_t w = ::waitpid(pid, &status, WNOHANG);
    if (w == pid) return status;
    if (w < 0 && errno != EINTR) fail("softcut sweep: waiting for a run failed (", std::strerror(errno), ")");
    if (!stopped && SignalGuard::flag().load()) stopped = ::kill(pid, SIGINT) == 0;  // finish the frame, write, exit
    ::usleep(20000);
  }
}

// Why a run failed, from its exit status and the end of its log (the last
// 1 MiB: a script may print megabytes before the error): the error or failed
// expectation the child printed, else the status.
std::string failure_of(int status, const fs::path& dir) {
  std::string tail;
  try {
    const UniqueFd fd = open_below(dir, "run.log", Access::read, "softcut sweep");
    struct stat st {};
    if (::fstat(fd.get(), &st) == 0) {
      const off_t from = std::max<off_t>(0, st.st_size - (off_t(1) << 20));
      tail.resize(std::size_t(st.st_size - from));
      const ssize_t n = ::pread(fd.get(), tail.data(), tail.size(), from);
      tail.resize(n > 0 ? std::size_t(n) : 0);
    }
  } catch (const Error&) {
  }
  std::string expect;
  for (size_t at = 0; at < tail.size();) {
    const size_t nl = std::min(tail.find('\n', at), tail.size());
    const std::string line = tail.substr(at, nl - at);
    at = nl + 1;
    if (line.rfind("softcut: error: ", 0) == 0) return line.substr(16);
    if (expect.empty() && line.find(": expect '") != std::string::npos) expect = line;
  }
  const std::string log = (dir / "run.log").string();
  if (!expect.empty()) return expect;
  if (WIFSIGNALED(status)) return cat("killed by signal ", WTERMSIG(status), " (see ", log, ")");
  if (WEXITSTATUS(status) == 130) return "interrupted (stopped after its frame, outputs written)";
  return cat("exit status ", WEXITSTATUS(status), " (see ", log, ")");
}

// A run that ended before its outputs started (a script error in the main
// chunk, a value the scenario refuses, a crash) wrote no summary: the sweep
// writes one saying so, so the merge tabulates it as failed instead of missing.
void write_failure_summary(const fs::path& dir, const std::vector<std::string>& argv, const std::string& reason) {
  Json j;
  j["schema"] = "softcut-summary/1";
  j["written_by"] = "softcut sweep: the run wrote no summary (see run.log)";
  j["command_line"] = argv;
  j["run"] = {{"frames", 0}, {"last_frame", -1}, {"last_time_s", nullptr}, {"exit_reason", "error"},
              {"message", reason}};
  j["expectations"] = Json::array();
  write_file_atomic(dir / "summary.json", json_text(j));
}

int cmd_merge(const Args& args) {
  Options o("softcut sweep merge", "Gathers every run's summary.json of a sweep into DIR/sweep.csv and "
            "DIR/sweep.json; fails naming the runs that have no summary.");
  std::vector<std::string> dirs;
  std::string csv_text, json_text_path;
  o.app().add_option("dir", dirs, "the sweep folder")->type_name("DIR");
  o.app().add_option("--csv", csv_text, "write the table here instead")->type_name("FILE");
  o.app().add_option("--json", json_text_path, "write the JSON here instead")->type_name("FILE");
  o.needs("--csv", "a file");
  o.needs("--json", "a file");
  if (!o.parse(args)) return 0;
  if (dirs.size() > 1) usage_fail("softcut sweep merge: give one sweep folder (got '", dirs[1], "' too)");
  if (dirs.empty()) usage_fail("softcut sweep merge: give the sweep folder (see softcut sweep --help)");
  const fs::path dir = dirs[0];
  fs::path csv = csv_text, json = json_text_path;
  std::error_code ec;
  if (!fs::exists(fs::symlink_status(dir / "sweep_plan.json", ec)))
    fail("softcut sweep merge: ", (dir / "sweep_plan.json").string(), " does not exist (not a sweep folder, or no "
         "shard has started yet)");
  const SweepMerge m = merge_sweep(dir);
  if (!m.missing.empty()) {
    std::string ids;
    for (size_t i = 0; i < m.missing.size() && i < 20; ++i) ids += (i ? ", " : "") + m.missing[i];
    if (m.missing.size() > 20) ids += cat(", ... (", m.missing.size() - 20, " more)");
    fail("softcut sweep merge: ", m.missing.size(), " of ", m.runs, " runs have no summary.json: ", ids,
         " (not run yet, or their process died; rerun their shard with the same options)");
  }
  if (csv.empty()) csv = dir / "sweep.csv";
  if (json.empty()) json = dir / "sweep.json";
  write_file_atomic(csv, m.csv);
  write_file_atomic(json, m.json);
  std::printf("merged %d runs: %d passed, %d failed -> %s, %s\n", m.runs, m.passed, m.failed, csv.c_str(),
              json.c_str());
  return m.failed ? 1 : 0;
}

}  // namespace

int cmd_sweep(const Args& args) {
  if (!args.empty() && args[0] == "merge") return cmd_merge(Args(args.begin() + 1, args.end()));
  Options o("softcut sweep", kSweepAbout, kSweepFooter);
  CLI::App& app = o.app();
  std::vector<std::string> grids, files;
  std::string table_text, out_text, shard_text;
  int jobs = 0, shards_count = 1;
  bool dry_run = false;
  app.add_option("scenario", files, "the scenario file")->type_name("SCENARIO.lua");
  o.add_list("--grid", grids, "a parameter's values (repeatable; the runs are the product of all grids)")
      ->type_name("key=v1,v2,...");
  app.add_option("--table", table_text, "one run per CSV row (a header of parameter names)")->type_name("FILE.csv");
  app.add_option("--out", out_text, "sweep folder (default: renders/<scenario file stem>-sweep)")->type_name("DIR");
  CLI::Option* jobs_opt = app.add_option("-j,--jobs", jobs, "runs at once (default: the cores this process may use)")
                              ->type_name("N")->check(whole_number(1, 100000));
  app.add_option("--shard", shard_text, "run only runs i with i % N == I (see below)")->type_name("I/N");
  app.add_option("--shards", shards_count, "shard count of a Kubernetes indexed Job (see below)")->type_name("N")
      ->check(whole_number(1, 1000000));
  app.add_flag("--dry-run", dry_run, "print this shard's runs and their parameters, run nothing");
  // Options for each `softcut run`, checked here so a typo fails once, not per run.
  RunOptions run(o, RunOptions::all);
  for (const auto& [option, what] :
       {std::pair{"--grid", "key=v1,v2,..."}, {"--table", "a CSV file"}, {"--out", "a folder"}, {"--jobs", "a number"},
        {"--shard", "I/N"}, {"--shards", "a number"}})
    o.needs(option, what);
  if (args.empty()) {
    std::fputs(o.help().c_str(), stderr);
    return 2;
  }
  if (!o.parse(args)) return 0;

  const std::vector<std::string> run_options = run.arguments();
  std::map<std::string, std::string> fixed;
  for (const auto& kv : run.sets()) {
    add_override(fixed, kv);
    const auto eq = kv.find('=');
    if (const std::string why = bad_value(kv.substr(eq + 1)); !why.empty())
      usage_fail("softcut sweep: --set ", printable(kv, 80), ": the value ", why);
  }
  const fs::path table = table_text;
  fs::path out = out_text;
  std::optional<std::string> shard_arg;
  if (app.count("--shard")) shard_arg = shard_text;
  std::optional<int> shards;
  if (app.count("--shards")) shards = shards_count;
  if (!jobs_opt->count()) jobs = usable_cores();
  if (files.size() != 1) usage_fail("softcut sweep: give exactly one scenario file (got ", files.size(), ")");
  if (grids.empty() == table.empty()) usage_fail("softcut sweep: give the runs as --grid key=v1,v2,... or as --table FILE.csv (one of them)");
  if (!fs::is_regular_file(files[0])) usage_fail("softcut sweep: ", printable(files[0]), ": no such scenario file");

  SweepPlan plan;
  plan.scenario = fs::absolute(files[0]).lexically_normal().string();
  plan.run_options = run_options;
  plan.runs = grids.empty() ? read_table(table, plan.keys) : expand_grid(grids, plan.keys);
  for (const auto& k : plan.keys)
    if (fixed.count(k)) usage_fail("softcut sweep: '", k, "' is both swept and fixed with --set");
  number_runs(plan.runs);
  const Shard shard = choose_shard(shard_arg, shards, [](const char* n) { return std::getenv(n); });
  const std::vector<std::size_t> mine = shard_runs(plan.runs.size(), shard);
  if (out.empty()) out = fs::path("renders") / (fs::path(files[0]).stem().string() + "-sweep");

  // The scenario takes the swept keys (declared in softcut.params, values it
  // accepts): checked on the first run before any process starts.
  {
    app::RunRequest req;
    run.apply(req);
    req.scenario = files[0];
    for (const auto& [k, v] : plan.runs.front().params) req.overrides[k] = v;
    const SignalGuard signals;
    req.interrupt = &SignalGuard::flag();
    const Watchdog dog(req.timeout_s, std::clamp(req.timeout_s / 10, 5.0, 60.0),
                       cat(files[0], ": the wall-clock limit of ", req.timeout_s, " s (--timeout) passed while the "
                           "script ran and it did not stop; exiting"));
    app::load_scenario_spec(req, [&dog](const RunRequest& q, OutputBudget* output, const Watchdog*) {
      return open_lua_scenario(q, output, &dog);
    });
  }
  const std::string plan_text = plan_json(plan);
  if (dry_run) {
    std::printf("%zu runs; %s runs %zu of them -> %s\n", plan.runs.size(),
                shard.source.empty() ? "this process" : shard.source.c_str(), mine.size(), out.c_str());
    for (std::size_t i : mine) std::printf("%s  %s\n", plan.runs[i].id.c_str(), params_text(plan.runs[i]).c_str());
    return 0;
  }
  std::error_code ec;
  fs::create_directories(out, ec);
  if (ec || !fs::is_directory(out)) fail("softcut sweep: cannot create the sweep folder ", out.string(), ": ", ec ? ec.message() : "not a folder");
  const fs::path plan_file = out / "sweep_plan.json";
  if (fs::exists(fs::symlink_status(plan_file, ec))) {
    if (read_file_below(out, "sweep_plan.json", "the sweep plan", kMaxPlanBytes) != plan_text)
      fail("softcut sweep: ", out.string(), " holds another sweep (its sweep_plan.json differs from this one: other "
           "parameters, options or scenario); give another --out or remove the folder");
  } else {
    write_file_atomic(plan_file, plan_text);  // every shard writes the same bytes
  }

  // Each child gets an even share of the cores unless the user chose, and
  // no more OpenBLAS threads than a run here would use (core/threads.hpp).
  std::vector<std::string> env;
  for (char** e = environ; *e; ++e) env.emplace_back(*e);
  const int at_once = std::max(1, std::min<int>(jobs, int(mine.size())));
  if (!std::getenv("SOFTCUT_THREADS"))
    env.push_back(cat("SOFTCUT_THREADS=", std::max(1, std::min(thread_policy().threads / at_once,
                                                                 thread_policy().blas_threads))));
  std::printf("sweep %s: %zu runs%s; %zu here, %d at once -> %s\n", files[0].c_str(), plan.runs.size(),
              shard.source.empty() ? "" : cat(" (", shard.source, ")").c_str(), mine.size(), at_once, out.c_str());
  std::fflush(stdout);

  const SignalGuard signals;
  struct Outcome {
    bool done = false, pass = false, ran = false;
    std::string reason;
    double seconds = 0;
  };
  std::vector<Outcome> outcomes(mine.size());
  std::atomic<size_t> next{0};
  std::mutex mutex;
  size_t printed = 0;
  int passed = 0, failed = 0;
  auto print_ready = [&] {  // under `mutex`
    for (; printed < mine.size() && outcomes[printed].done; ++printed) {
      const Outcome& o = outcomes[printed];
      const SweepRun& r = plan.runs[mine[printed]];
      if (o.pass) {
        ++passed;
        std::printf("PASS  %s  %s  (%.2f s)\n", r.id.c_str(), params_text(r).c_str(), o.seconds);
      } else {
        ++failed;
        std::printf("FAIL  %s  %s: %s\n", r.id.c_str(), params_text(r).c_str(), printable(o.reason, 400).c_str());
      }
    }
    std::fflush(stdout);
  };
  auto worker = [&] {
    for (size_t k; (k = next++) < mine.size();) {
      const SweepRun& r = plan.runs[mine[k]];
      Outcome o;
      const auto t0 = std::chrono::steady_clock::now();
      if (SignalGuard::flag().load()) {
        o.reason = "interrupted before it ran";
      } else {
        fs::path dir;
        std::vector<std::string> argv;
        try {
          dir = make_folder_below(out, r.id, "softcut sweep");
          argv = {"softcut", "run", plan.scenario, "--out", dir.string(), "--quiet"};
          for (const auto& [key, v] : r.params) argv.insert(argv.end(), {"--set", key + "=" + v});
          argv.insert(argv.end(), run_options.begin(), run_options.end());
          // An earlier run's summary must not stand for this one (a run that
          // fails before its outputs start would leave it in place).
          sim::clear_earlier_outputs(dir);
          const int status = spawn_and_wait(argv, dir / "run.log", env);
          o.ran = true;
          o.pass = WIFEXITED(status) && WEXITSTATUS(status) == 0;
          if (!o.pass) o.reason = failure_of(status, dir);
        } catch (const std::exception& e) {
          o.reason = e.what();
        }
        // A run that could not start, or ended before its outputs, is a
        // failed row of the merge, not a missing one.
        std::error_code ec;
        if (!dir.empty() && !fs::exists(fs::symlink_status(dir / "summary.json", ec))) {
          try {
            write_failure_summary(dir, argv, o.reason);
          } catch (const std::exception&) {
          }
        }
      }
      o.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
      o.done = true;
      std::lock_guard<std::mutex> lock(mutex);
      outcomes[k] = std::move(o);
      print_ready();
    }
  };
  std::vector<std::thread> threads;
  for (int t = 1; t < at_once; ++t) threads.emplace_back(worker);
  worker();
  for (auto& t : threads) t.join();
  std::printf("%d passed, %d failed\n", passed, failed);
  if (SignalGuard::flag().load()) return 130;
  return failed ? 1 : 0;
}

}  // namespace softcut::app
