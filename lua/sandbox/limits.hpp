#pragma once
// The sandbox's budgets, shared by the allocator, the count hook and the
// wrapped library functions (sandbox/limits.cpp, sandbox/io.cpp):
// - memory: every Lua allocation and the engine memory held for the script;
// - instructions: counted by the hook, plus work done inside C functions,
//   which the hook never sees, charged by size (bytes allocated, elements
//   moved, bytes written);
// - CPU time per call (sandbox/cpu_limit.hpp): what one instruction does in
//   C, which neither the hook nor the charges see;
// - stops from outside: Ctrl-C / SIGTERM (interrupt) and the wall-clock
//   watchdog (deadline).
// Running out of instructions or CPU time, an interrupt and the deadline are FATAL and
// sticky: once hit, the hook fails every later instruction, pcall, xpcall
// and coroutine.resume/close re-raise instead of returning, and the Runtime
// refuses every later call, so no script can catch its way past them.
#include <atomic>
#include <cstddef>
#include <string>

#include "runtime.hpp"
#include "sandbox/cpu_limit.hpp"

struct lua_State;
struct lua_Debug;

namespace softcut {
class OutputBudget;
}

namespace softcut::lua {

struct Runtime::Budget {
  std::size_t used = 0;           // Lua heap, bytes
  std::size_t native = 0;         // engine memory held for the script (mesh handles), bytes
  std::size_t limit = 0;          // 0: unlimited
  bool memory_exceeded = false;   // set when an allocation was refused
  long long instructions = 0;     // this call's, including charged C work
  long long instruction_limit = 0;  // 0: unlimited
  const std::atomic<bool>* interrupt = nullptr;  // SIGINT/SIGTERM
  const std::atomic<bool>* deadline = nullptr;   // the wall-clock watchdog fired
  double timeout_s = 0;                          // for the deadline's message
  double cpu_limit_s = 0;         // CPU time per call, s; 0: none
  double cpu_start_s = 0;         // this thread's CPU clock when the call began, plus exempted engine work, s
  bool cpu_timer = false;         // the timer is armed (else the hook polls the clock)
  int cpu_polls = 0;
  CpuTimer timer;
  OutputBudget* output = nullptr;                // bytes the script writes (io.write, file:write)
  bool fatal = false;             // sticky: see above
  std::string fatal_message;      // "file:line: instruction budget ... exceeded ..."
  int calls_active = 0;           // Runtime::call frames running: engine work is the script's then
  bool reading_spec = false;      // the engine reads the script's tables after it ran: charged too
  int close_depth = 0;            // nested coroutine.close calls (Lua 5.4.4 overflows the C stack on deep ones)
  int require_depth = 0;          // nested requires of the scenario's own modules
};

// The budget of the state (the allocator's user data), and its options.
Runtime::Budget* budget_of(lua_State* L);
const SandboxOptions& options_of(lua_State* L);

// The allocator and count hook the Runtime installs.
void* budget_alloc(void* ud, void* ptr, std::size_t osize, std::size_t nsize);
void count_hook(lua_State* L, lua_Debug* ar);
constexpr int kHookInterval = 1000;  // instructions between count-hook calls

// Charges `instructions` of work a C function is about to do (`what`:
// "string.rep"); when the budget cannot pay for it, turns fatal and raises
// before the work is done. For use inside lua_CFunctions only (it may
// longjmp: no C++ object with a destructor may be alive in the caller).
void charge_or_raise(lua_State* L, double instructions, const char* what);

// lua_load of `text` in pieces, checking the call's CPU time between them
// (Lua's parser takes quadratic time on some inputs, and no hook runs while
// it parses): past the limit the load fails and the stop is fatal. Status
// and stack as luaL_loadbufferx.
int load_text(lua_State* L, const char* text, size_t n, const char* chunkname, const char* mode);

// Raises the sticky fatal error (pushes its message; never returns).
int raise_fatal(lua_State* L);

// A call into the script begins or ends (Runtime::call): starts and stops
// its CPU-time clock (sandbox/cpu_limit.hpp).
void begin_call(lua_State* L, Runtime::Budget* b);
void end_call(Runtime::Budget* b);

// For the sandbox's wrappers: calls the wrapped function (upvalue 1) with
// every argument on the stack and returns the number of its results
// (`nresults`, or all of them with LUA_MULTRET).
int call_original(lua_State* L, int nresults = -1 /* LUA_MULTRET */);
// The same in a protected call: an error the original raised without a
// position (luaL_error inside a wrapped C function sees the wrapper, a C
// function, as its caller) gets the script's file:line, and "to '?'" the
// function's `name` ("string.rep"); fatal stops go on unchanged.
int call_original_placed(lua_State* L, int nresults, const char* name);

// Replaces pcall, xpcall, coroutine.resume/close (re-raise fatal errors),
// setmetatable (refuses __gc: finalizers run with Lua's hooks off, where no
// budget reaches them) and wraps the C library functions whose work grows
// with their arguments (string.rep, table.concat/move/insert/remove/sort/
// unpack, utf8.len/offset, load, collectgarbage) so that work is charged.
void install_sandbox_limits(lua_State* L);
// Only the fatal-error half of it (pcall & co.): also used with --trust, so
// that Ctrl-C and the deadline stop a trusted script too.
void install_sticky_stops(lua_State* L);

// Sandboxed io: io.open / io.lines through the checked open below the
// scenario folder (read) or the output folder (write), file:write and
// io.write charged to the instruction budget and the output budget, no
// seeking past the end of a file, no reading from stdin. The io table is left
// on the stack.
void push_sandboxed_io(lua_State* L);

}  // namespace softcut::lua
