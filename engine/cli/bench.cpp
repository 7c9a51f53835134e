#include "cli/bench.hpp"

namespace softcut::cli {

// Add a line here when a bench_<name>.cpp lands.
const std::vector<Benchmark>& benchmarks() {
  static const std::vector<Benchmark> all = {};
  return all;
}

}  // namespace softcut::cli
