// The benchmark list and the `softcut bench` command.
#include "bench/bench.hpp"

#include <cstdio>

#include "core/error.hpp"

namespace softcut::bench {

int bench_hybrid(const Args& args);    // hybrid.cpp
int bench_assembly(const Args& args);  // assembly.cpp
int bench_gpu(const Args& args);       // gpu.cpp
int bench_render(const Args& args);    // render.cpp
int bench_springs(const Args& args);   // springs.cpp
int bench_cut(const Args& args);       // cut.cpp
int bench_nonlinear(const Args& args); // nonlinear.cpp

// Add a line here when a bench/<name>.cpp lands.
const std::vector<Benchmark>& benchmarks() {
  static const std::vector<Benchmark> all = {
      {"hybrid", "hybrid condensed model vs monolithic (paper Tables 2-5)", bench_hybrid},
      {"assembly", "stiffness assembly vs triplets; CHOLMOD and CG solve times by tet count", bench_assembly},
      {"gpu", "compute-shader SpMV bandwidth and CG iteration time vs CPU by system size", bench_gpu},
      {"render", "off-screen frame cost (colour, depth and labels, video) against the simulated frame; softcut render against the run", bench_render},
      {"springs", "implicit grasper springs per frame: explicit vs implicit with and without the compliance cache",
       bench_springs},
      {"cut", "cutting in the operational region: cut, rebuild and warm/cold frame vs region size (paper Fig. 8)", bench_cut},
      {"nonlinear", "a corotational hybrid frame vs the same mixed model solved whole by Newton, and vs the linear frame",
       bench_nonlinear},
  };
  return all;
}

}  // namespace softcut::bench

namespace softcut::app {

int cmd_bench(const Args& args) {
  if (args.empty() || args[0] == "--help" || args[0] == "-h") {
    std::printf("usage: softcut bench NAME [options]\n\nbenchmarks:\n");
    for (const auto& b : bench::benchmarks()) std::printf("  %-12s %s\n", b.name, b.summary);
    return args.empty() ? 2 : 0;
  }
  for (const auto& b : bench::benchmarks())
    if (args[0] == b.name) return b.run(Args(args.begin() + 1, args.end()));  // bad options: UsageError, exit 2
  usage_fail("bench: unknown benchmark '", args[0], "' (softcut bench --help lists them)");
}

}  // namespace softcut::app
