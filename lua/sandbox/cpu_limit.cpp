#include "sandbox/cpu_limit.hpp"

#include <lua.hpp>
#include <signal.h>
#include <sys/syscall.h>
#include <time.h>
#include <unistd.h>

#include <cmath>
#include <mutex>

#include "sandbox/limits.hpp"

namespace softcut::lua {

namespace {

// Set by Runtime::call, the count hook and the coroutine wrappers; read by
// the signal handler on the same thread (initial-exec TLS: no allocation on
// first access inside a handler).
__attribute__((tls_model("initial-exec"))) thread_local lua_State* t_running = nullptr;

// A real-time signal nobody else in the process uses (glibc keeps the first
// two for its threads; SIGRTMIN accounts for them).
int cpu_signal() { return SIGRTMIN + 4; }

// Asks Lua to call the count hook at the running state's next instruction.
// Lua documents lua_sethook as safe to call from a signal handler.
extern "C" void on_cpu_signal(int) {
  if (lua_State* L = t_running) lua_sethook(L, count_hook, LUA_MASKCOUNT, 1);
}

bool install_handler() {
  static std::once_flag once;
  static bool ok = false;
  std::call_once(once, [] {
    struct sigaction sa {};
    sa.sa_handler = on_cpu_signal;
    sigemptyset(&sa.sa_mask);
    sa.sa_flags = SA_RESTART;  // a read or write the signal lands in goes on
    ok = ::sigaction(cpu_signal(), &sa, nullptr) == 0;
  });
  return ok;
}

timespec to_timespec(double s) {
  timespec t{};
  t.tv_sec = time_t(s);
  t.tv_nsec = long((s - double(t.tv_sec)) * 1e9);
  if (t.tv_sec == 0 && t.tv_nsec == 0) t.tv_nsec = 1;  // zero would disarm
  return t;
}

}  // namespace

double thread_cpu_seconds() {
  timespec t{};
  ::clock_gettime(CLOCK_THREAD_CPUTIME_ID, &t);
  return double(t.tv_sec) + 1e-9 * double(t.tv_nsec);
}

void set_running_state(lua_State* L) { t_running = L; }
lua_State* running_state() { return t_running; }

CpuTimer::~CpuTimer() {
  if (made_) ::timer_delete(static_cast<timer_t>(timer_));
}

bool CpuTimer::arm(double seconds) {
  if (!(seconds > 0) || !std::isfinite(seconds) || !install_handler()) return false;
  const int tid = int(::syscall(SYS_gettid));
  if (made_ && tid_ != tid) {  // another thread (or a forked child, where the timer does not exist)
    ::timer_delete(static_cast<timer_t>(timer_));
    made_ = false;
  }
  if (!made_) {
    sigevent ev{};
    ev.sigev_notify = SIGEV_THREAD_ID;
    ev.sigev_signo = cpu_signal();
    ev._sigev_un._tid = tid;  // sigev_notify_thread_id (glibc 2.36 names it only this way)
    timer_t t{};
    // The clock of the calling thread: the one that runs the script.
    if (::timer_create(CLOCK_THREAD_CPUTIME_ID, &ev, &t) != 0) return false;
    timer_ = t, made_ = true, tid_ = tid;
  }
  // Then every 50 ms of CPU more: a signal that lands while the hook resets
  // its own interval is not lost for good.
  itimerspec spec{};
  spec.it_value = to_timespec(seconds);
  spec.it_interval = to_timespec(0.05);
  return ::timer_settime(static_cast<timer_t>(timer_), 0, &spec, nullptr) == 0;
}

void CpuTimer::disarm() {
  if (!made_) return;
  itimerspec spec{};
  ::timer_settime(static_cast<timer_t>(timer_), 0, &spec, nullptr);
}

CpuExempt::CpuExempt(lua_State* L) : L_(L), start_(thread_cpu_seconds()) {}

CpuExempt::~CpuExempt() {
  // The call's clock starts later by the time spent here.
  budget_of(L_)->cpu_start_s += thread_cpu_seconds() - start_;
}

}  // namespace softcut::lua
