#pragma once
// What a scenario asks of the elastic solve: the operational backend and the
// solver's options (ScenarioSpec::solver). Plain data; backend/solver.hpp
// turns it into a Solver.
#include <filesystem>
#include <limits>
#include <string_view>

#include "hybrid/precompute.hpp"
#include "solve/newton.hpp"

namespace softcut::backend {

// The operational backend (backend::choose_backend): automatic (CHOLMOD on the
// operational system, the fastest exact solver measured), cpu (block-Jacobi
// CG, the paper's solver), gpu (compute-shader CG in the application's EGL
// context, also on llvmpipe; an error without a context), direct (CHOLMOD,
// what automatic picks on a CPU), monolithic (no hybrid: whole-mesh CHOLMOD
// reference, for checks). Nonlinear frames go through Newton on each: PCG
// preconditioned by the kept factor (direct, monolithic) or, on the CG
// backends, block Jacobi on the CPU (hybrid/nonlinear_solve). Parsed once,
// where the text enters (Lua, CLI).
enum class Backend { automatic, cpu, gpu, direct, monolithic };
// The names users write: "auto", "cpu", "gpu", "direct", "monolithic".
const char* to_string(Backend b);
// Throws softcut::Error naming the accepted values.
Backend parse_backend(std::string_view text);

struct SolverSpec {
  double cg_tolerance = 1e-10;  // relative residual of the operational CG
  int cg_max_iterations = 0;    // 0: automatic
  Backend backend = Backend::automatic;
  bool gpu_fp64 = false;        // gpu: fp64 kernels instead of fp32 + fp64 refinement
  // How the nonoperational data is kept (hybrid/precompute.hpp's Storage;
  // named as in Lua, s:solver{ mode }).
  hybrid::Storage mode = hybrid::Storage::automatic;
  // The most the precomputed nonoperational data may take, bytes (the
  // runner sets the sandbox's memory budget); more is an error.
  double max_bytes = std::numeric_limits<double>::infinity();
  // Precompute cache folder (hybrid/precompute_cache.hpp; the CLI's default
  // is hybrid::default_cache_dir(), --no-cache clears it); empty: no cache.
  std::filesystem::path cache_dir;
  // Nonlinear frames (DESIGN.md §1b): Newton's tolerance and limits.
  solve::NewtonOptions newton;
  // Every tet takes its material's law and nothing is condensed: the whole
  // body solved by Newton (backend monolithic; for bodies small enough).
  bool whole_body = false;
};

}  // namespace softcut::backend
