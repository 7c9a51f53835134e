// Outputs that cannot be written: a folder that cannot be created or written,
// and a full disk (simulated by RLIMIT_FSIZE with SIGXFSZ ignored, so writes
// fail with EFBIG exactly where ENOSPC would). Each ends with a clear
// softcut::Error naming the path, and leaves no partial or temporary files.
#include <doctest/doctest.h>

#include <csignal>
#include <string>

#include "core/atomic_file.hpp"
#include "hardening_support.hpp"
#include "app/scenario_run.hpp"

namespace fs = std::filesystem;
using softcut::hardening::contains;
using softcut::hardening::count_files;
using softcut::hardening::error_of;
using softcut::hardening::in_child;
using softcut::hardening::put_file;

namespace {

// A 5x2x2-cell box logging every surface node for 3 s at 30 fps: a CSV of
// ~100 kB, far above the 16 kB file size limit used below.
const char* kScenario = R"(
local s = softcut.scenario{ name = "hardening_out", duration = 3, fps = 30 }
s:mesh{ generate = "box", options = { min = {0, 0, 0}, max = {0.1, 0.04, 0.04}, nx = 5, ny = 2, nz = 2 } }
s:material{ tissue = "liver" }
s:fix{ nodes = softcut.select.box{ min = {0, 0, 0}, max = {0, 0.04, 0.04} } }
local tip = softcut.select.box{ min = {0.1, 0, 0}, max = {0.1, 0.04, 0.04} }
s:load{ name = "pull", nodes = tip, force = {0, 0, -0.01}, ramp = softcut.ramp.linear{ t1 = 1 } }
return s
)";

fs::path scenario_in(const std::string& name) {
  const fs::path dir = softcut::test::scratch_dir(name);
  return put_file(dir / "scenario.lua", kScenario);
}

int leftovers(const fs::path& dir) {
  return count_files(dir, ".tmp") + count_files(dir, ".partial");
}

}  // namespace

TEST_SUITE("hardening/output_limits") {
  TEST_CASE("write_file_atomic on a full disk: Error naming the file, no temporary left") {
    const fs::path dir = softcut::test::scratch_dir("hardening_atomic_full");
    const int rc = in_child(RLIMIT_FSIZE, 16 << 10, [&] {
      std::signal(SIGXFSZ, SIG_IGN);
      const std::string msg = error_of([&] { softcut::write_file_atomic(dir / "big.bin", std::string(1 << 20, 'x')); });
      if (msg.empty()) return 1;
      if (!contains(msg, "big.bin")) return 2;
      return 0;
    });
    CHECK(rc == 0);
    CHECK(!fs::exists(dir / "big.bin"));
    CHECK(leftovers(dir) == 0);
  }

  TEST_CASE("write_file_atomic into a missing folder or onto a folder: Error naming the path") {
    const fs::path dir = softcut::test::scratch_dir("hardening_atomic_bad");
    CHECK(contains(error_of([&] { softcut::write_file_atomic(dir / "no" / "such" / "f.txt", "x"); }), "f.txt"));
    fs::create_directories(dir / "taken");
    CHECK(contains(error_of([&] { softcut::write_file_atomic(dir / "taken", "x"); }), "taken"));
    CHECK(leftovers(dir) == 0);
  }

  TEST_CASE("a run whose output folder cannot be created fails with a softcut::Error naming it") {
    softcut::app::RunRequest req;
    req.scenario = scenario_in("hardening_out_blocked");
    put_file(req.scenario.parent_path() / "blocker", "a file where a folder should be");
    req.out_dir = req.scenario.parent_path() / "blocker" / "out";
    req.render = false;
    std::string msg;
    try {
      softcut::app::run_scenario(req);
    } catch (const softcut::Error& e) {
      msg = e.what();
    } catch (const std::exception& e) {
      FAIL_CHECK("not a softcut::Error: " << std::string(e.what()));
      return;
    }
    INFO(msg);
    CHECK(contains(msg, "blocker"));
  }

  TEST_CASE("softcut run into a folder that is not writable: clear message, exit status 1") {
    const fs::path sc = scenario_in("hardening_out_cli_blocked");
    put_file(sc.parent_path() / "blocker", "x");
    const auto r = softcut::hardening::run_softcut("run --quiet --out blocker/out scenario.lua", sc.parent_path());
    INFO(r.output);
    CHECK(r.status == 1);
    CHECK(contains(r.output, "blocker"));
    CHECK(leftovers(sc.parent_path()) == 0);
  }

  TEST_CASE("softcut run on a full disk: clear message, no partial files") {
    const fs::path sc = scenario_in("hardening_out_full");
    // dash and bash: `ulimit -f` in 512- or 1024-byte blocks; SIGXFSZ ignored so writes fail with EFBIG.
    const auto r = softcut::hardening::run_softcut("run --quiet --out out scenario.lua", sc.parent_path(),
                                                   "trap '' XFSZ; ulimit -f 32;");
    INFO(r.output);
    CHECK(r.status == 1);
    CHECK(contains(r.output, "disk full"));
    CHECK(!fs::exists(sc.parent_path() / "out" / "displacements.csv"));
    CHECK(leftovers(sc.parent_path()) == 0);
  }
}
