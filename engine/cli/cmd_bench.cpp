// softcut bench NAME: each benchmark reports ratios against a baseline measured
// in the same run (never absolute wall-clock assertions).
#include <cstdio>

#include "cli/bench.hpp"
#include "cli/commands.hpp"
#include "core/error.hpp"

namespace softcut::cli {

int cmd_bench(const Args& args) {
  if (args.empty() || args[0] == "--help" || args[0] == "-h") {
    std::printf("usage: softcut bench NAME [options]\n\nbenchmarks:\n");
    for (const auto& b : benchmarks()) std::printf("  %-12s %s\n", b.name, b.summary);
    return args.empty() ? 2 : 0;
  }
  for (const auto& b : benchmarks())
    if (args[0] == b.name) return b.run(Args(args.begin() + 1, args.end()));  // bad options: UsageError, exit 2
  usage_fail("bench: unknown benchmark '", args[0], "' (softcut bench --help lists them)");
}

}  // namespace softcut::cli
