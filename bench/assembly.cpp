// softcut bench assembly: stiffness assembly time against tet count on Kuhn
// boxes, block-pattern assembler (threaded and serial) against Eigen's
// setFromTriplets baseline measured in the same run; plus the clamped box's
// static solve by CHOLMOD (factor + solve) and by block-Jacobi CG.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <ctime>
#include <sstream>
#include <thread>

#include "bench/bench.hpp"
#include "app/option_values.hpp"
#include "app/options.hpp"
#include "core/atomic_file.hpp"
#include "core/error.hpp"
#include "core/timer.hpp"
#include "fem/assembly.hpp"
#include "fem/dof_map.hpp"
#include "bench/box_problem.hpp"
#include "solve/cg.hpp"
#include "solve/cholesky.hpp"

namespace softcut::bench {

namespace {

struct Row {
  int tets = 0, nodes = 0, dofs = 0;
  double block_ms = 0, serial_ms = 0, serial_cpu_ms = 0, triplet_ms = 0;
  double chol_factor_ms = -1, chol_solve_ms = -1;
  double cg_ms = 0, cg_residual = 0;
  int cg_iterations = 0;
  bool cg_converged = false;
  double cg_vs_direct = -1;  // relative difference of the two solutions
};

Row measure(int target, int repeat, int threads, int direct_max) {
  // Near-cubic box with about `target` tets (6 per cell).
  const double cells = std::max(1.0, target / 6.0);
  const int n = std::max(1, int(std::lround(std::cbrt(cells))));
  const int nx = std::max(1, int(std::lround(cells / (double(n) * n))));
  const BoxProblem box = box_problem({{nx, n, n}, Eigen::Vector3d(nx, n, n) * 0.01, 0, 0});  // 1 cm cells
  const mesh::TetMesh& m = box.mesh;
  const std::vector<fem::Material>& mats = box.materials;

  Row row;
  row.tets = m.num_tets();
  row.nodes = m.num_nodes();
  fem::SparseMatrix K, Kt, Ks;
  row.block_ms = min_ms(repeat, [&] { K = fem::assemble_stiffness(m, mats, {}, threads); });
  row.serial_ms = min_ms(repeat, [&] { Ks = fem::assemble_stiffness(m, mats, {}, 1); });
  // Process CPU time of one serial assembly: the cost without the wait for
  // a core on a loaded machine.
  const std::clock_t c0 = std::clock();
  Ks = fem::assemble_stiffness(m, mats, {}, 1);
  row.serial_cpu_ms = 1e3 * double(std::clock() - c0) / CLOCKS_PER_SEC;
  row.triplet_ms = min_ms(repeat, [&] { Kt = fem::assemble_stiffness_triplets(m, mats); });
  if ((K - Kt).norm() > 1e-12 * Kt.norm() || (K - Ks).norm() != 0)
    fail("bench assembly: the assemblers disagree on ", row.tets, " tets");

  // Clamped at x = 0, unit downward load on the x = max face.
  std::vector<char> free_node(static_cast<size_t>(m.num_nodes()));
  Eigen::VectorXd f = Eigen::VectorXd::Zero(3 * m.num_nodes());
  for (int i = 0; i < m.num_nodes(); ++i) {
    free_node[size_t(i)] = !box.fixed_mask[size_t(i)];
    if (m.nodes(i, 0) >= nx * 0.01) f(3 * i + 2) = -1e-3;
  }
  const fem::DofMap map = fem::make_dof_map(free_node);
  const fem::SparseMatrix A = fem::restrict_matrix(K, map);
  const Eigen::VectorXd b = fem::restrict_vector(f, map);
  row.dofs = map.size();

  Eigen::VectorXd x_direct;
  if (row.tets <= direct_max) {
    Timer t;
    const solve::Cholesky chol(A, "bench box");
    row.chol_factor_ms = t.ms();
    t.reset();
    solve::SolveWorkspace ws;
    chol.solve_into(b, x_direct, ws);
    row.chol_solve_ms = t.ms();
  }
  Timer t;
  solve::BlockJacobi pre(A);
  pre.finalize();
  Eigen::VectorXd x;
  const solve::CgResult r = solve::pcg(solve::sparse_operator(A), pre.as_operator(), b, x, {1e-8, 0});
  row.cg_ms = t.ms();
  row.cg_iterations = r.iterations;
  row.cg_residual = r.relative_residual;
  row.cg_converged = r.converged;
  if (x_direct.size() > 0) row.cg_vs_direct = (x - x_direct).norm() / x_direct.norm();
  return row;
}

std::string num(double v, const char* fmt = "%.1f") {
  if (v < 0) return "-";
  char buf[64];
  std::snprintf(buf, sizeof buf, fmt, v);
  return buf;
}

}  // namespace

int bench_assembly(const Args& args) {
  app::Options o("softcut bench assembly", "Stiffness assembly of Kuhn boxes against Eigen's setFromTriplets in "
                 "the same run; CHOLMOD and CG solve times by tet count.");
  std::vector<int> sizes;
  int repeat = 3, threads = 0, direct_max = 60000;  // threads 0: assemble_stiffness decides, as in the engine
  std::string json;
  o.add_list("--tets", sizes, "target tet count of a Kuhn box (repeatable; default 1000 5000 20000 50000 100000 "
             "200000)")->type_name("N")->check(app::whole_number(1, 100000000));
  o.app().add_option("--repeat", repeat, "timings are the minimum over R runs (default 3)")->type_name("R")
      ->check(app::whole_number(1, 100000000));
  o.app().add_option("--threads", threads, cat("threads of the block assembler (default: the engine's "
                     "automatic choice, 1 below 20000 tets, else ", std::thread::hardware_concurrency(), " here)"))
      ->type_name("T")->check(app::whole_number(1, 100000000));
  o.app().add_option("--direct-max-tets", direct_max, "CHOLMOD only up to N tets (default 60000; its fill grows "
                     "fast on cubes)")->type_name("N")->check(app::whole_number(1, 100000000));
  o.app().add_option("--json", json, "also write the rows as JSON")->type_name("FILE");
  o.needs("--json", "a file name");
  if (!o.parse(args)) return 0;
  if (sizes.empty()) sizes = {1000, 5000, 20000, 50000, 100000, 200000};

  std::printf("Stiffness assembly on Kuhn boxes (E = 3 kPa, nu = 0.45), minimum of %d runs, threads: %s;\n"
              "baseline = Eigen setFromTriplets in the same run. Solves: x = 0 face clamped, end-face load,\n"
              "CG with block-Jacobi to relative residual 1e-8.\n\n",
              repeat, threads > 0 ? std::to_string(threads).c_str() : "automatic");
  std::printf("| tets | nodes | free DOFs | block ms | block 1-thread ms | (CPU ms) | triplets ms | speedup vs triplets "
              "| CHOLMOD factor ms | CHOLMOD solve ms | CG ms | CG iterations | CG vs CHOLMOD |\n");
  std::printf("|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|\n");
  std::vector<Row> rows;
  for (int target : sizes) {
    const Row r = measure(target, repeat, threads, direct_max);
    rows.push_back(r);
    std::printf("| %d | %d | %d | %s | %s | %s | %s | %sx | %s | %s | %s | %d%s | %s |\n", r.tets, r.nodes,
                r.dofs, num(r.block_ms).c_str(), num(r.serial_ms).c_str(), num(r.serial_cpu_ms).c_str(),
                num(r.triplet_ms).c_str(),
                num(r.triplet_ms / r.block_ms, "%.2f").c_str(), num(r.chol_factor_ms).c_str(),
                num(r.chol_solve_ms).c_str(), num(r.cg_ms).c_str(), r.cg_iterations,
                r.cg_converged ? "" : " (not converged)", num(r.cg_vs_direct, "%.1e").c_str());
    std::fflush(stdout);
  }
  if (!json.empty()) {
    Json j = {{"benchmark", "assembly"}, {"threads", threads}, {"repeat", repeat}, {"rows", Json::array()}};
    // Negative CHOLMOD times: not run (past --direct-max-tets).
    auto direct = [](double v) { return v < 0 ? Json(nullptr) : field(v); };
    for (const Row& r : rows)
      j["rows"].push_back({{"tets", r.tets}, {"nodes", r.nodes}, {"free_dofs", r.dofs}, {"block_ms", field(r.block_ms)},
                           {"block_serial_ms", field(r.serial_ms)}, {"block_serial_cpu_ms", field(r.serial_cpu_ms)},
                           {"triplet_ms", field(r.triplet_ms)},
                           {"speedup_vs_triplets", field(r.triplet_ms / r.block_ms)},
                           {"cholmod_factor_ms", direct(r.chol_factor_ms)}, {"cholmod_solve_ms", direct(r.chol_solve_ms)},
                           {"cg_ms", field(r.cg_ms)}, {"cg_iterations", r.cg_iterations},
                           {"cg_relative_residual", field(r.cg_residual)}, {"cg_converged", r.cg_converged},
                           {"cg_vs_cholmod", direct(r.cg_vs_direct)}});
    write_file_atomic(json, json_text(j));
    std::printf("\nwrote %s\n", json.c_str());
  }
  return 0;
}

}  // namespace softcut::bench
