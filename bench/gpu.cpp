// softcut bench gpu: the operational solve's kernels on the device against the
// CPU in the same run — SpMV bandwidth (GB/s) and time per CG iteration by
// system size, so one sees where launch overhead dominates and where the
// device pulls ahead. On llvmpipe (no GPU) the "device" is the CPU itself.
#include <cmath>
#include <cstdio>
#include <sstream>

#include "bench/bench.hpp"
#include "app/option_values.hpp"
#include "app/options.hpp"
#include "core/atomic_file.hpp"
#include "core/error.hpp"
#include "core/timer.hpp"
#include "fem/assembly.hpp"
#include "fem/dof_map.hpp"
#include "fem/whole_mesh.hpp"
#include "gpu/compute_cg.hpp"
#include "bench/box_problem.hpp"
#include "solve/cg.hpp"

namespace softcut::bench {
namespace {

struct Row {
  int cells = 0, dofs = 0;
  long nnz = 0;
  double cpu_spmv_us = 0, gpu_spmv_us = 0, cpu_gbs = 0, gpu_gbs = 0;
  double cpu_iter_us = 0, gpu_iter_us = 0;
};

}  // namespace

int bench_gpu(const Args& args) {
  app::Options o("softcut bench gpu", "Compute-shader SpMV bandwidth and CG iteration time against the CPU, by "
                 "system size.");
  std::vector<int> cells;
  int iterations = 50;
  double peak = 0;
  std::string json;
  bool fp64 = false;
  o.add_list("--cells", cells, "box of 2N x N x N Kuhn cells (repeatable; default 4 8 12 16 24)")->type_name("N")
      ->check(app::whole_number(1, 99999));
  o.app().add_option("--iterations", iterations, "CG iterations timed per size (default 50)")->type_name("K")
      ->check(app::whole_number(1, 99999));
  o.app().add_flag("--fp64", fp64, "double-precision kernels");
  o.app().add_option("--peak-gbs", peak, "the device's peak memory bandwidth, to report the fraction reached")
      ->type_name("G")->check(app::open_interval(0, INFINITY, "a positive bandwidth in GB/s"));
  o.app().add_option("--json", json, "also write the rows as JSON")->type_name("FILE");
  if (!o.parse(args)) return 0;
  if (cells.empty()) cells = {4, 8, 12, 16, 24};

  gl::EglContext context;
  std::printf("device: %s\n", context.info().summary().c_str());
  gpu::ComputeCgOptions opt;
  opt.fp64 = fp64;
  gpu::ComputeCg cg(context, opt);
  const double scalar = fp64 ? 8 : 4;

  std::vector<Row> rows;
  for (int c : cells) {
    const BoxProblem box = box_problem({{2 * c, c, c}, {0.2, 0.1, 0.1}, 0, 0});
    const mesh::TetMesh& m = box.mesh;
    const fem::WholeMesh whole(m, box.materials, box.fixed_mask);
    const fem::SparseMatrix& K = whole.K();
    const auto bs = gpu::make_block_system(K);
    cg.set_system(bs);

    Row r;
    r.cells = c;
    r.dofs = int(K.rows());
    r.nnz = long(K.nonZeros());
    const Eigen::VectorXd x = Eigen::VectorXd::Random(K.rows());
    Eigen::VectorXd y(K.rows());
    const int reps = std::max(5, int(2e7 / double(r.nnz)));
    Timer t;
    for (int k = 0; k < reps; ++k) y.noalias() = K * x;
    r.cpu_spmv_us = t.seconds() / reps * 1e6;
    // Bytes a SpMV must move at least: values + indices + x + y.
    const double cpu_bytes = double(r.nnz) * (8 + 4) + 2.0 * 8 * r.dofs;
    const double gpu_bytes = double(bs.col.size()) * (9 * scalar + 4) + 4.0 * bs.row_ptr.size() + 2.0 * scalar * r.dofs;
    r.cpu_gbs = cpu_bytes / (r.cpu_spmv_us * 1e3);
    r.gpu_spmv_us = cg.time_spmv(reps) * 1e6;
    r.gpu_gbs = gpu_bytes / (r.gpu_spmv_us * 1e3);

    // CG iterations at a fixed count (tolerance unreachable).
    solve::BlockJacobi M(K);
    M.finalize();
    solve::CgOptions co;
    co.tolerance = 1e-30;
    co.max_iterations = iterations;
    Eigen::VectorXd xs;
    t.reset();
    solve::pcg(solve::sparse_operator(K), M.as_operator(), x, xs, co);
    r.cpu_iter_us = t.seconds() / iterations * 1e6;
    cg.options().max_inner_iterations = iterations;
    Eigen::VectorXd d;
    t.reset();
    const int done = cg.solve_device(x, d, 1e-30);
    r.gpu_iter_us = t.seconds() / std::max(done, 1) * 1e6;
    rows.push_back(r);
  }

  std::printf("\n| cells | DOFs | nnz | CPU SpMV µs | GB/s | GPU SpMV µs | GB/s%s | CPU CG µs/it | GPU CG µs/it | GPU/CPU per it |\n",
              peak > 0 ? " (of peak)" : "");
  std::printf("|---|---|---|---|---|---|---|---|---|---|\n");
  for (const Row& r : rows) {
    char frac[32] = "";
    if (peak > 0) std::snprintf(frac, sizeof frac, " (%.0f%%)", 100 * r.gpu_gbs / peak);
    std::printf("| %d | %d | %ld | %.1f | %.2f | %.1f | %.2f%s | %.1f | %.1f | %.2f |\n", r.cells, r.dofs, r.nnz,
                r.cpu_spmv_us, r.cpu_gbs, r.gpu_spmv_us, r.gpu_gbs, frac, r.cpu_iter_us, r.gpu_iter_us,
                r.gpu_iter_us / r.cpu_iter_us);
  }
  if (!json.empty()) {
    // The device's name is the driver's text: escaped like any string.
    Json j = {{"device", context.info().summary()}, {"fp64", fp64}, {"rows", Json::array()}};
    for (const Row& r : rows)
      j["rows"].push_back({{"cells", r.cells}, {"dofs", r.dofs}, {"nnz", r.nnz}, {"cpu_spmv_us", field(r.cpu_spmv_us)},
                           {"cpu_gbs", field(r.cpu_gbs)}, {"gpu_spmv_us", field(r.gpu_spmv_us)},
                           {"gpu_gbs", field(r.gpu_gbs)}, {"cpu_iter_us", field(r.cpu_iter_us)},
                           {"gpu_iter_us", field(r.gpu_iter_us)}});
    write_file_atomic(json, json_text(j));
  }
  return 0;
}

}  // namespace softcut::bench
