#pragma once
// Benchmark registry: one bench_<name>.cpp per benchmark, listed in bench.cpp.
#include <vector>

#include "cli/commands.hpp"

namespace softcut::cli {

struct Benchmark {
  const char* name;
  const char* summary;
  int (*run)(const Args& args);
};

const std::vector<Benchmark>& benchmarks();

}  // namespace softcut::cli
