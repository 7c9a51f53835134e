#pragma once
// softcut bench NAME: the benchmarks, one file each (bench/<name>.cpp, listed
// in bench.cpp). Each reports ratios against a baseline measured in the same
// run, never absolute wall-clock claims (bench/README.md). They sit above the
// application (engine/cli: option parsing, scenario runs), which they use;
// the program's `bench` command (cli::cmd_bench) is defined here.
#include <type_traits>
#include <vector>

#include "cli/commands.hpp"
#include "core/json_text.hpp"

namespace softcut::bench {

using cli::Args;

struct Benchmark {
  const char* name;
  const char* summary;
  int (*run)(const Args& args);
};

const std::vector<Benchmark>& benchmarks();

// A field of a JSON report (--json, written with core/json_text): counts as
// they are, times and ratios to 6 significant digits, null when not finite.
template <class T>
Json field(T v) {
  if constexpr (std::is_floating_point_v<T>) return json_number(double(v), 6);
  else return v;
}

}  // namespace softcut::bench
