#include "sim/run.hpp"

#include <doctest/doctest.h>

#include <atomic>
#include <fstream>
#include <set>
#include <sstream>

#include "core/error.hpp"
#include "fixtures.hpp"
#include "sim/outputs.hpp"
#include "test_support.hpp"

namespace fs = std::filesystem;
namespace sim = softcut::sim;

using softcut::test::slurp;

namespace {

// Frame numbers of a displacements.csv, checking every row is complete.
std::vector<int> csv_frames(const fs::path& p, size_t rows_per_frame) {
  std::ifstream in(p);
  std::string line;
  std::getline(in, line);
  CHECK(line == "frame,time,node,ux,uy,uz");
  std::vector<int> frames;
  size_t rows = 0;
  while (std::getline(in, line)) {
    CHECK(std::count(line.begin(), line.end(), ',') == 5);
    const int f = std::stoi(line.substr(0, line.find(',')));
    if (frames.empty() || frames.back() != f) frames.push_back(f);
    rows++;
  }
  CHECK(rows == frames.size() * rows_per_frame);
  return frames;
}

sim::RunResult run_in(const fs::path& dir, const sim::Model& m, const sim::RunHooks& hooks) {
  sim::State s = sim::make_state(m);
  sim::Recorder rec(m, dir);
  return sim::run(m, s, rec, hooks);
}

}  // namespace

TEST_SUITE("sim/run") {
  TEST_CASE("interrupt after k frames: valid CSV with exactly k frames, summary marked interrupted") {
    const fs::path dir = softcut::test::scratch_dir("sim_run_interrupt");
    const sim::Model m = sim::compile(softcut::test::cantilever_spec(dir, 2.0));
    REQUIRE(m.num_frames == 21);
    std::atomic<bool> stop{false};
    sim::RunHooks hooks;
    hooks.interrupt = &stop;
    int progress_calls = 0;
    hooks.on_frame = [&](const sim::Model&, sim::State& s) {
      if (s.frame == 4) stop = true;  // as a signal handler would, during frame k = 5
      return true;
    };
    hooks.progress = [&](int frame, int n, double elapsed) {
      progress_calls++;
      CHECK(n == 21);
      CHECK(elapsed >= 0);
    };
    const sim::RunResult r = run_in(dir, m, hooks);
    CHECK(r.frames == 5);
    CHECK(r.reason == sim::ExitReason::interrupted);
    CHECK(progress_calls == 5);
    CHECK(!fs::exists(dir / "displacements.csv.partial"));
    CHECK(csv_frames(dir / "displacements.csv", m.log_nodes.size()) == std::vector<int>{0, 1, 2, 3, 4});
    const std::string summary = slurp(dir / "summary.json");
    CHECK(summary.find("\"interrupted\": true") != std::string::npos);
    CHECK(summary.find("\"exit_reason\": \"interrupted\"") != std::string::npos);
    CHECK(summary.find("\"frames\": 5") != std::string::npos);
  }

  TEST_CASE("the same spec twice gives byte-identical CSVs") {
    const fs::path a = softcut::test::scratch_dir("sim_run_det_a"), b = softcut::test::scratch_dir("sim_run_det_b");
    auto spec = softcut::test::cantilever_spec(a, 0.5);
    spec.loads[0].magnitude = softcut::tools::Ramp::sine_wave(0.002, 0.01, 1.3, 0.2);
    const sim::RunResult ra = run_in(a, sim::compile(spec), {});
    const sim::RunResult rb = run_in(b, sim::compile(spec), {});
    CHECK(ra.reason == sim::ExitReason::completed);
    CHECK(ra.frames == 6);
    const std::string ca = slurp(a / "displacements.csv"), cb = slurp(b / "displacements.csv");
    CHECK(ca.size() > 1000);
    CHECK(ca == cb);
  }

  TEST_CASE("script stop, frame limit, and an error in the hook still leave complete outputs") {
    const fs::path dir = softcut::test::scratch_dir("sim_run_stop");
    const sim::Model m = sim::compile(softcut::test::cantilever_spec(dir, 1.0));
    {
      sim::RunHooks hooks;
      hooks.on_frame = [](const sim::Model&, sim::State& s) { return s.frame < 2; };
      const sim::RunResult r = run_in(dir, m, hooks);
      CHECK(r.reason == sim::ExitReason::stopped);
      CHECK(csv_frames(dir / "displacements.csv", m.log_nodes.size()).size() == 3);
    }
    {
      sim::RunHooks hooks;
      hooks.max_frames = 4;
      const sim::RunResult r = run_in(dir, m, hooks);
      CHECK(r.reason == sim::ExitReason::frame_limit);
      CHECK(r.frames == 4);
    }
    {
      sim::RunHooks hooks;
      hooks.on_frame = [](const sim::Model&, sim::State& s) -> bool {
        if (s.frame == 1) softcut::fail("scene.lua:7: expectation failed");
        return true;
      };
      CHECK_THROWS_WITH_AS(run_in(dir, m, hooks), doctest::Contains("scene.lua:7"), softcut::Error);
      CHECK(csv_frames(dir / "displacements.csv", m.log_nodes.size()).size() == 2);
      const std::string summary = slurp(dir / "summary.json");
      CHECK(summary.find("\"exit_reason\": \"error\"") != std::string::npos);
      CHECK(summary.find("scene.lua:7: expectation failed") != std::string::npos);
    }
  }
}
