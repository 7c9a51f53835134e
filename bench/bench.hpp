#pragma once
// softcut bench NAME: the benchmarks, one file each (bench/<name>.cpp, listed
// in bench.cpp). Each reports ratios against a baseline measured in the same
// run, never absolute wall-clock claims (bench/README.md). They sit above the
// application (engine/cli: option parsing, scenario runs), which they use;
// the program's `bench` command (cli::cmd_bench) is defined here.
#include <vector>

#include "cli/commands.hpp"

namespace softcut::bench {

using cli::Args;

struct Benchmark {
  const char* name;
  const char* summary;
  int (*run)(const Args& args);
};

const std::vector<Benchmark>& benchmarks();

}  // namespace softcut::bench
