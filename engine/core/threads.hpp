#pragma once
// How many threads softcut's parallel parts use: OpenBLAS inside CHOLMOD's
// factorizations, the precompute's block solves, stage 5's dense product,
// the precompute cache's reads.
// Measured on 2 cores (box_20736, docs/hybrid.md): alone, 2 BLAS threads make
// the precompute 16 % faster than 1; two runs side by side with 2 threads
// each take 1.6x longer than with 1 each (OpenBLAS threads spin and fight).
// So: $SOFTCUT_THREADS when set; else the idle cores (cores minus the 1-minute
// load average, at least 1).
// OpenBLAS gets at most kDefaultBlasThreads of those unless SOFTCUT_THREADS
// asks for more. Measured on an NVIDIA H100 machine's 16 cores (a Firecracker
// VM; docs/hybrid.md, Threads): on 16 OpenBLAS threads CHOLMOD's factorizations
// ran 6-24x slower than on this 2-core machine's 2 threads (the ligament's
// K22 factor 142 ms against 6 ms, box_111132's 10.0 s against 1.6 s): the
// supernodal factor makes hundreds of small BLAS calls, and OpenBLAS's dtrsm
// threads every one of them (no size threshold; SuiteSparse issue 1).
//
//   const ThreadPolicy& t = thread_policy();  // decided once, at first use
//   apply_blas_threads(t.blas_threads);       // the CLI does this at start
#include <string>

namespace softcut {

inline constexpr int kDefaultBlasThreads = 2;

struct ThreadPolicy {
  int threads = 1;       // softcut's own parallel parts
  int blas_threads = 1;  // OpenBLAS's: threads, at most kDefaultBlasThreads unless SOFTCUT_THREADS is set
  std::string reason;    // "SOFTCUT_THREADS=1", "2 cores, load 0.1: 2 idle", "16 cores, ...: 16 idle, BLAS on 2", ...
};

// Decided on first call from the environment and /proc/loadavg.
const ThreadPolicy& thread_policy();

// The policy for a SOFTCUT_THREADS value (null: unset), a core count and a
// 1-minute load average.
ThreadPolicy thread_policy_for(const char* softcut_threads, int cores, double load);

// Sets OpenBLAS's thread count (when the BLAS in use is OpenBLAS; found at
// run time, so any BLAS links) and OpenMP's. Returns false when neither is there.
bool apply_blas_threads(int threads);

// OpenBLAS's thread count now, or 0 when the BLAS in use is not OpenBLAS.
int blas_threads();

// OpenBLAS on one thread while any such scope is open in the process (the
// hybrid precompute's block solves run side by side on single-threaded
// BLAS; the direct backend's refactor on a second thread keeps one open
// from its launch to its adoption), then back to the count before the first
// one opened. Scopes may overlap on several threads (softcut check -j); the
// count changes only when it differs, and check -j already runs every
// scenario on one BLAS thread, so scopes there change nothing while other
// runs call BLAS. A scope opens and closes at points of the run's own
// sequence (never at a time another thread happens to finish), so a run's
// BLAS calls see the same count whatever the timing.
class SingleThreadedBlas {
 public:
  SingleThreadedBlas();
  ~SingleThreadedBlas();
  SingleThreadedBlas(const SingleThreadedBlas&) = delete;
  SingleThreadedBlas& operator=(const SingleThreadedBlas&) = delete;
};

}  // namespace softcut
