#include "core/threads.hpp"

#include <dlfcn.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <fstream>
#include <mutex>
#include <thread>

#include "core/error.hpp"

namespace softcut {

namespace {

ThreadPolicy decide() {
  double load = 0;  // thread_policy_for takes NaN and negative values as 0
  std::ifstream in("/proc/loadavg");
  if (!(in >> load)) load = 0;
  return thread_policy_for(std::getenv("SOFTCUT_THREADS"), int(std::max(1u, std::thread::hardware_concurrency())),
                           load);
}

}  // namespace

ThreadPolicy thread_policy_for(const char* softcut_threads, int cores, double load) {
  ThreadPolicy p;
  if (const char* v = softcut_threads; v && *v) {
    char* end = nullptr;
    const long n = std::strtol(v, &end, 10);
    if (end && *end == '\0' && n >= 1 && n <= 1024) {
      p.threads = p.blas_threads = int(n);
      p.reason = cat("SOFTCUT_THREADS=", n);
      return p;
    }
    p.reason = cat("SOFTCUT_THREADS='", v, "' ignored (want 1..1024); ");
  }
  cores = std::max(1, cores);
  if (!std::isfinite(load) || load < 0) load = 0;
  const int idle = std::max(1, cores - int(std::lround(std::min(load, double(cores)))));
  p.threads = idle;
  p.blas_threads = std::min(idle, kDefaultBlasThreads);
  p.reason += cat(cores, " cores, load ", std::round(load * 100) / 100, ": ", idle, " idle");
  if (p.blas_threads < idle) p.reason += cat(", BLAS on ", p.blas_threads);
  return p;
}

const ThreadPolicy& thread_policy() {
  static const ThreadPolicy p = decide();
  return p;
}

int blas_threads() {
  using GetFn = int (*)();
  if (auto f = reinterpret_cast<GetFn>(::dlsym(RTLD_DEFAULT, "openblas_get_num_threads"))) return f();
  return 0;
}

namespace {
std::mutex blas_scope_mu;
int blas_scopes = 0;   // open SingleThreadedBlas scopes
int blas_before = 0;   // the count before the first opened
}  // namespace

SingleThreadedBlas::SingleThreadedBlas() {
  std::lock_guard lk(blas_scope_mu);
  if (blas_scopes++ == 0) {
    blas_before = blas_threads();
    if (blas_before > 1) apply_blas_threads(1);
  }
}

SingleThreadedBlas::~SingleThreadedBlas() {
  std::lock_guard lk(blas_scope_mu);
  if (--blas_scopes == 0 && blas_before > 1) apply_blas_threads(blas_before);
}

bool apply_blas_threads(int threads) {
  bool any = false;
  using SetFn = void (*)(int);
  if (auto f = reinterpret_cast<SetFn>(::dlsym(RTLD_DEFAULT, "openblas_set_num_threads"))) f(threads), any = true;
  if (auto f = reinterpret_cast<SetFn>(::dlsym(RTLD_DEFAULT, "omp_set_num_threads"))) f(threads), any = true;
  return any;
}

}  // namespace softcut
