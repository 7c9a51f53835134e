// softcut command-line program: dispatches to the subcommands in commands.hpp.
#include <csignal>
#include <cstdio>
#include <exception>
#include <string>

#include "app/commands.hpp"
#include "core/error.hpp"
#include "core/stop_flags.hpp"
#include "core/threads.hpp"
#include "core/printable.hpp"

namespace {

const char* kUsage =
    "softcut " SOFTCUT_VERSION " - scripted surgical soft-tissue simulation (Wu & Heng 2005 hybrid FEM)\n"
    "\n"
    "usage: softcut <command> [options]\n"
    "\n"
    "commands:\n"
    "  run SCENARIO.lua [--out DIR] [--set key=value ...] [--frames N] [--backend B]\n"
    "                   [--depth] [--labels] [--video] [--quiet] [--trust] [--no-render]\n"
    "                       run a Lua scenario headless; logs and frames under renders/<name>/\n"
    "  render RUNDIR [--eye X,Y,Z --target X,Y,Z] [--fov D] [--size WxH] [--style S] [--video]\n"
    "                       redraw a finished run's frames from its record, without simulating\n"
    "  check PATH... [-j N] [--only PAT] [--exclude PAT] [--set key=value ...] [--timeout S]\n"
    "                [--junit FILE] [--json FILE] [--record [--force]] [--backend B] [--out DIR]\n"
    "                [--max-output BYTES] [--trust]\n"
    "                       run scenarios' expectations and compare with their reference logs\n"
    "  sweep SCENARIO.lua (--grid key=v1,v2,... | --table FILE.csv) [-j N] [--shard I/N] [--out DIR]\n"
    "                       run a scenario once per parameter combination, on one machine or sharded\n"
    "  sweep merge DIR      gather a sweep's summaries into DIR/sweep.csv and DIR/sweep.json\n"
    "  mesh info FILE [--json] [--unit U]\n"
    "  mesh convert IN OUT [--unit U] [--scale S]\n"
    "                       convert between mesh formats (by extension), in metres\n"
    "  mesh generate KIND [options] OUT\n"
    "                       box, cylinder, tube, band, ligament, upper_leg, liver, kidney, knee_ligament,\n"
    "                       surface (STL/OBJ/PLY/OFF) or volume (NRRD labels)\n"
    "  bench NAME [options] benchmarks (ratios against a baseline in the same run)\n"
    "\n"
    "  B (backend): auto, cpu, gpu, direct or monolithic\n"
    "  --help, -h           this text (also: softcut <command> --help)\n"
    "  --version            print the version\n";

}  // namespace

int main(int argc, char** argv) {
  using namespace softcut::app;
  if (argc < 2) {
    std::fputs(kUsage, stderr);
    return 2;
  }
  const std::string cmd = argv[1];
  if (cmd == "--help" || cmd == "-h" || cmd == "help") {
    std::fputs(kUsage, stdout);
    return 0;
  }
  if (cmd == "--version") {
    std::printf("softcut %s\n", SOFTCUT_VERSION);
    return 0;
  }
  // Past a file-size limit (ulimit -f, systemd's LimitFSIZE) a write fails
  // with EFBIG instead of killing the process: every writer then takes its
  // "write failed (disk full?)" path, removes its temporary file and says so.
  // Ignored signals stay ignored across exec: `sweep`'s runs inherit it.
  std::signal(SIGXFSZ, SIG_IGN);
  const Args args(argv + 2, argv + argc);
  // BLAS threads that do not fight other runs for the cores (core/threads.hpp).
  softcut::apply_blas_threads(softcut::thread_policy().blas_threads);
  try {
    if (cmd == "mesh") return cmd_mesh(args);
    if (cmd == "bench") return cmd_bench(args);
    if (cmd == "run") return cmd_run(args);
    if (cmd == "check") return cmd_check(args);
    if (cmd == "sweep") return cmd_sweep(args);
    if (cmd == "render") return cmd_render(args);
    std::fprintf(stderr, "softcut: unknown command '%s' (see softcut --help)\n", cmd.c_str());
    return 2;
  } catch (const softcut::UsageError& e) {
    std::fprintf(stderr, "softcut: error: %s\n", softcut::printable(e.what(), 8192, true).c_str());
    return 2;
  } catch (const softcut::TimeoutError& e) {
    std::fprintf(stderr, "softcut: error: %s\n", softcut::printable(e.what(), 8192, true).c_str());
    return 124;
  } catch (const softcut::InterruptedError& e) {  // Ctrl-C / SIGTERM before the frame loop (the loop's own: 130 too)
    std::fprintf(stderr, "softcut: error: %s\n", softcut::printable(e.what(), 8192, true).c_str());
    return 130;
  } catch (const softcut::Error& e) {
    // Messages carry bytes from scripts and files: shown escaped and bounded.
    std::fprintf(stderr, "softcut: error: %s\n", softcut::printable(e.what(), 8192, true).c_str());
    return 1;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "softcut: internal error: %s\n", e.what());
    return 3;
  }
}
