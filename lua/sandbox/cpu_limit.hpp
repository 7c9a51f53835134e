#pragma once
// The sandbox's CPU-time limit per call into the script (main chunk, each
// on_frame or check function; SandboxOptions::cpu_seconds).
//
// The count hook sees VM instructions, but one instruction may do O(n) work
// in C that no hook sees: a float key colliding in a 2e6-entry hash chain,
// comparing two 1 MiB strings in table.sort, arithmetic on a 64 MiB numeric
// string, a 2000-deep __index chain. A thousand of them between two hook
// calls take minutes. So the kernel keeps the time: a POSIX timer on the
// calling thread's CPU clock (CLOCK_THREAD_CPUTIME_ID) signals that thread
// when the call's CPU time reaches the limit, and the handler only asks Lua
// to call the count hook at the next instruction (lua_sethook may be called
// from a signal handler: lua.c stops scripts on Ctrl-C that way). The hook
// then reads the clock and, past the limit, makes the stop fatal and sticky
// like the instruction budget. Nothing runs per instruction.
//
// Engine work a binding does for the script whose cost has its own bound
// (generating or reading a mesh: the mesh size limit) is exempted
// (CpuExempt), so a 2M-tet organ meshed in 30 s still fits a call.
struct lua_State;

namespace softcut::lua {

// This thread's CPU time, s.
double thread_cpu_seconds();

// The coroutine (or main state) running on this thread, which the timer's
// signal marks for a hook call; null outside calls into the script.
void set_running_state(lua_State* L);
lua_State* running_state();

class CpuTimer {
 public:
  CpuTimer() = default;
  ~CpuTimer();
  CpuTimer(const CpuTimer&) = delete;
  CpuTimer& operator=(const CpuTimer&) = delete;

  // Signals this thread after `seconds` more of its CPU time. False when no
  // timer can be made (then the hook polls the clock instead).
  bool arm(double seconds);
  void disarm();

 private:
  bool made_ = false;
  int tid_ = 0;  // the thread the timer measures and signals
  void* timer_ = nullptr;  // timer_t
};

// Scope of engine work that the CPU-time limit does not count (see above).
class CpuExempt {
 public:
  explicit CpuExempt(lua_State* L);
  ~CpuExempt();
  CpuExempt(const CpuExempt&) = delete;
  CpuExempt& operator=(const CpuExempt&) = delete;

 private:
  lua_State* L_;
  double start_;
};

}  // namespace softcut::lua
