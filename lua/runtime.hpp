#pragma once
// The Lua 5.4 runtime a scenario runs in: one lua_State with the sandbox
// (safe libraries only, file access limited to two folders, text chunks only,
// an instruction budget and a memory budget), the embedded Lua-side library
// as `softcut`, and calls that turn every Lua error into a softcut::Error
// whose message starts with the user's file:line (runtime errors also carry
// a traceback). No physics here: see wrap_*.cpp for the engine bindings.
#include <atomic>
#include <cstddef>
#include <filesystem>
#include <functional>
#include <string>
#include <string_view>

struct lua_State;

namespace softcut {
class OutputBudget;
}

namespace softcut::lua {

struct SandboxOptions {
  bool trusted = false;                     // --trust: full standard library, no budgets
  std::filesystem::path read_dir;           // io.open(..., "r") allowed below it (scenario folder)
  std::filesystem::path write_dir;          // io.open(..., "w"/"a") allowed below it (output folder)
  long long instruction_budget = 200'000'000;  // Lua VM instructions per call from C++ (main chunk, each on_frame)
  double cpu_seconds = 10;                     // CPU time per call from C++, s (sandbox/cpu_limit.hpp); 0: none
  std::size_t memory_budget = 512u << 20;      // bytes held by the Lua heap and the script's meshes at any time
  double max_tets = 2'000'000;                 // tetrahedra of the mesh the script loads or generates
  const std::atomic<bool>* interrupt = nullptr;  // when set, running Lua code stops with "interrupted"
  const std::atomic<bool>* deadline = nullptr;   // when set (the watchdog), running Lua code stops
  double timeout_s = 0;                          // the watchdog's limit, for messages
  OutputBudget* output = nullptr;                // bytes the script may write (with the engine's outputs)
};

class Runtime {
 public:
  explicit Runtime(const SandboxOptions& opt = {});
  ~Runtime();
  Runtime(const Runtime&) = delete;
  Runtime& operator=(const Runtime&) = delete;

  lua_State* state() const { return L_; }
  const SandboxOptions& options() const { return opt_; }

  // Loads `path` as a text chunk named "@path" and calls it with no arguments;
  // leaves `nresults` results on the stack. Throws softcut::Error.
  void run_file(const std::filesystem::path& path, int nresults);
  // The same for a file's text already read (through the checked open);
  // `path` names the chunk.
  void run_source(std::string text, const std::filesystem::path& path, int nresults);
  // Same for a string (tests, --set parsing); `chunkname` like "=[test]".
  void run_string(std::string_view code, const std::string& chunkname, int nresults);
  // Calls the function below `nargs` arguments on the stack, with the
  // traceback handler; throws softcut::Error carrying the Lua message.
  void call(int nargs, int nresults);

  // Pushes the library's private table (bindings, overrides, scenario_dir).
  void push_internal();
  // The output folder, once known (io.open for writing is allowed below it).
  void set_write_dir(const std::filesystem::path& dir) { opt_.write_dir = dir; }
  // Whether the instruction budget, an interrupt or the deadline has stopped
  // the script: then every later call() fails at once (sandbox/limits.hpp).
  bool stopped() const;

  // Lua heap plus engine memory held for the script, bytes; VM instructions executed by the current or last
  // call (in steps of the hook interval).
  std::size_t memory_used() const;
  long long instructions_used() const;

  struct Budget;  // heap and instruction accounting (sandbox/limits.hpp)

 private:
  SandboxOptions opt_;
  Budget* budget_ = nullptr;
  std::string chunk_;  // the scenario file, for messages without a Lua stack
  lua_State* L_ = nullptr;
};

// Calls f() and converts a C++ exception into a Lua error (the message of
// softcut::Error unchanged) without unwinding C++ frames by longjmp. Every
// binding body goes through it.
int protect(lua_State* L, const std::function<int()>& f);

// The sandbox's limit on a mesh's tetrahedra (SandboxOptions::max_tets;
// infinite with --trust).
double max_tets(lua_State* L);

// Charges `instructions` of native work (a binding's loops, where the count
// hook never fires) to the instruction budget, so that a short loop of
// expensive calls also ends at the budget. Throws softcut::Error naming the
// script's line and `what` once it is spent (call it inside protect()).
// No-op with --trust, and when no script function is on the stack (the
// engine reading the spec after the script has run).
void charge_work(lua_State* L, double instructions, const std::string& what);

// Engine memory a binding keeps alive for the script (a mesh handle) counts
// with the Lua heap against the memory budget. charge_memory throws naming
// `what` when it does not fit, after a full collection has let dead handles
// go; release_memory gives it back (from __gc). No limit with --trust.
void charge_memory(lua_State* L, std::size_t bytes, const std::string& what);
void release_memory(lua_State* L, std::size_t bytes);

// Whether the sandbox lets the scenario read `path` (always with --trust):
// engine bindings that open files (mesh files) ask this first.
bool may_read(lua_State* L, const std::filesystem::path& path);

// "file:line" of the innermost function that runs from a user chunk (source
// "@..."), or "?" when none: where a binding's error should point.
std::string user_where(lua_State* L);
// user_where(L) + ": ", or "" when it is "?": a message prefix.
std::string user_prefix(lua_State* L);

}  // namespace softcut::lua
