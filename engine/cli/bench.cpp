#include "cli/bench.hpp"

namespace softcut::cli {

int bench_hybrid(const Args& args);  // bench_hybrid.cpp
int bench_assembly(const Args& args);  // bench_assembly.cpp
int bench_gpu(const Args& args);  // bench_gpu.cpp
int bench_render(const Args& args);  // bench_render.cpp
int bench_springs(const Args& args);  // bench_springs.cpp
int bench_cut(const Args& args);  // bench_cut.cpp

// Add a line here when a bench_<name>.cpp lands.
const std::vector<Benchmark>& benchmarks() {
  static const std::vector<Benchmark> all = {
      {"hybrid", "hybrid condensed model vs monolithic (paper Tables 2-5)", bench_hybrid},
      {"assembly", "stiffness assembly vs triplets; CHOLMOD and CG solve times by tet count", bench_assembly},
      {"gpu", "compute-shader SpMV bandwidth and CG iteration time vs CPU by system size", bench_gpu},
      {"render", "off-screen frame cost (extract, draw, read back, PNG) against the simulated frame", bench_render},
      {"springs", "implicit grasper springs per frame: explicit vs implicit with and without the compliance cache",
       bench_springs},
      {"cut", "cutting in the operational region: cut, rebuild and warm/cold frame vs region size (paper Fig. 8)", bench_cut},
  };
  return all;
}

}  // namespace softcut::cli
