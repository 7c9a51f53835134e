// The test executables' main: doctest's, after the thread policy the CLI
// applies at start (app/main.cpp). Without it OpenBLAS and OpenMP
// start one thread per core in every test process, and with ctest --parallel
// their idle threads spin against the other processes' work.
#define DOCTEST_CONFIG_IMPLEMENT
#include <doctest/doctest.h>

#include "core/threads.hpp"

int main(int argc, char** argv) {
  softcut::apply_blas_threads(softcut::thread_policy().blas_threads);
  return doctest::Context(argc, argv).run();
}
