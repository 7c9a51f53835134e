#pragma once
// How many threads softcut's parallel parts use: OpenBLAS inside CHOLMOD's
// factorizations, the precompute's block solves, stage 5's dense product,
// the precompute cache's reads.
// Measured on 2 cores (box_20736, docs/hybrid.md): alone, 2 BLAS threads make
// the precompute 16 % faster than 1; two runs side by side with 2 threads
// each take 1.6x longer than with 1 each (OpenBLAS threads spin and fight).
// So: $SOFTCUT_THREADS when set; else the idle cores (cores minus the 1-minute
// load average, at least 1).
//
//   const ThreadPolicy& t = thread_policy();  // decided once, at first use
//   apply_blas_threads(t.threads);            // the CLI does this at start
#include <string>

namespace softcut {

struct ThreadPolicy {
  int threads = 1;
  std::string reason;  // "SOFTCUT_THREADS=1", "2 cores, load 0.1: 2 idle", ...
};

// Decided on first call from the environment and /proc/loadavg.
const ThreadPolicy& thread_policy();

// Sets OpenBLAS's thread count (when the BLAS in use is OpenBLAS; found at
// run time, so any BLAS links) and OpenMP's. Returns false when neither is there.
bool apply_blas_threads(int threads);

// OpenBLAS on `threads` threads for a scope, then on the policy's again
// (hybrid precompute: its block solves run side by side on single-threaded
// BLAS). Not for scopes that overlap on several threads.
class BlasThreadsScope {
 public:
  explicit BlasThreadsScope(int threads) { apply_blas_threads(threads); }
  ~BlasThreadsScope() { apply_blas_threads(thread_policy().threads); }
  BlasThreadsScope(const BlasThreadsScope&) = delete;
  BlasThreadsScope& operator=(const BlasThreadsScope&) = delete;
};

}  // namespace softcut
