#pragma once
// softcut bench NAME: the benchmarks, one file each (bench/<name>.cpp, listed
// in bench.cpp). Each reports ratios against a baseline measured in the same
// run, never absolute wall-clock claims (bench/README.md). They sit above the
// application (app/: option parsing, scenario runs), which they use;
// the program's `bench` command (app::cmd_bench) is defined here.
#include <algorithm>
#include <string>
#include <type_traits>
#include <vector>

#include "app/commands.hpp"
#include "core/json_text.hpp"
#include "core/timer.hpp"

namespace softcut::bench {

using app::Args;

struct Benchmark {
  const char* name;
  const char* summary;
  int (*run)(const Args& args);
};

const std::vector<Benchmark>& benchmarks();

// The timing rules. Minimum wall time (ms) of `repeat` calls: the cost of
// the work itself on a machine that may be busy (assembly, cut).
template <class F>
double min_ms(int repeat, F&& f) {
  double best = 1e300;
  for (int r = 0; r < repeat; ++r) {
    Timer t;
    f();
    best = std::min(best, t.ms());
  }
  return best;
}
// Median wall time (ms) of `reps` calls: a frame as a user sees it (hybrid).
template <class F>
double median_ms(int reps, F&& f) {
  std::vector<double> t;
  for (int r = 0; r < reps; ++r) {
    Timer tm;
    f();
    t.push_back(tm.ms());
  }
  std::nth_element(t.begin(), t.begin() + t.size() / 2, t.end());
  return t[t.size() / 2];
}

// A field of a JSON report (--json, written with core/json_text): counts as
// they are, times and ratios to 6 significant digits, null when not finite.
template <class T>
Json field(T v) {
  if constexpr (std::is_floating_point_v<T>) return json_number(double(v), 6);
  else return v;
}

}  // namespace softcut::bench
