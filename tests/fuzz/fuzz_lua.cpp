// libFuzzer target: the scenario loader. The input is a scenario script,
// written to scratch()/scenario.lua and loaded in the sandbox (no --trust)
// with tight budgets, so an endless loop or a memory hog ends with
// softcut::Error instead of a libFuzzer timeout / OOM. Only the script part
// runs (the Lua scenario script's spec): no model compile, no outputs. The budgets are
// tight on purpose: loading the library takes ~6e3 instructions and ~0.3 MiB
// and a small scenario loads well within 1e5 instructions and 8 MiB (lua/runtime
// "tight budgets" test), while a runaway input ends 20x sooner than under the
// former 2e6 instructions.
#include "fuzz_support.hpp"
#include "scenario_script.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace softcut;
  lua::ScriptRequest req;
  req.scenario = fuzz::put_file("scenario.lua", fuzz::as_text(data, size));
  req.sandbox.instruction_budget = 100'000;
  req.sandbox.memory_budget = 8u << 20;
  // A generator is refused before it allocates; the default (2e6) would
  // spend seconds per input on native work.
  req.sandbox.max_tets = 5000;
  // Work inside one instruction that no budget counts ends here, well
  // before libFuzzer's 10 s timeout (the default, 10 s, would meet it).
  req.sandbox.cpu_seconds = 1;
  fuzz::expect_clean([&] { lua::open_scenario(req)->spec(); });
  return 0;
}
