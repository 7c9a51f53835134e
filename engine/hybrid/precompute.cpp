#include "hybrid/precompute.hpp"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <exception>
#include <functional>
#include <mutex>
#include <thread>

#include "core/error.hpp"
#include "core/printable.hpp"
#include "core/threads.hpp"
#include "core/timer.hpp"
#include "fem/assembly.hpp"
#include "hybrid/loads.hpp"
#include "hybrid/precompute_estimate.hpp"
#include "hybrid/schur_complement.hpp"

namespace softcut::hybrid {

const char* to_string(Storage s) {
  switch (s) {
    case Storage::automatic: return "automatic";
    case Storage::dense: return "dense";
    case Storage::product: return "product";
    case Storage::factor: return "factor";
  }
  return "?";
}

Storage parse_storage(std::string_view text) {
  if (text == "auto") return Storage::automatic;
  for (Storage s : {Storage::dense, Storage::product, Storage::factor})
    if (text == to_string(s)) return s;
  fail("solver: unknown mode '", printable(text), "' (use auto, dense, product or factor)");
}

namespace {

// fn(c0, w, ws) for the column blocks [c0, c0 + w) of 0..n, B wide, on
// `threads` threads (1 or 2), each with its own CHOLMOD workspace, blocks
// claimed in turn. OpenBLAS runs single-threaded meanwhile: two block solves
// side by side beat one after the other on two BLAS threads (box_111132's
// 256-column K22 solves: 1.66-1.69 s against 2.80-2.85 s for two blocks),
// and a block's bits are the same on either thread and whatever the policy.
void for_column_blocks(Eigen::Index n, Eigen::Index B, int threads,
                       const std::function<void(Eigen::Index, Eigen::Index, solve::SolveWorkspace&)>& fn) {
  const Eigen::Index blocks = (n + B - 1) / B;
  if (blocks == 0) return;
  const SingleThreadedBlas single;
  std::atomic<Eigen::Index> next{0};
  std::mutex mu;
  std::exception_ptr error;
  auto work = [&] {
    solve::SolveWorkspace ws;
    for (Eigen::Index b; (b = next.fetch_add(1)) < blocks;) {
      try {
        fn(b * B, std::min(B, n - b * B), ws);
      } catch (...) {
        std::lock_guard lk(mu);
        if (!error) error = std::current_exception();
        next.store(blocks);  // the other thread stops after its block
      }
    }
  };
  if (threads >= 2 && blocks >= 2) {
    std::thread helper(work);
    work();
    helper.join();
  } else {
    work();
  }
  if (error) std::rethrow_exception(error);
}

// Refuses, before K^non is assembled, a model whose assembly or K22 factor
// would pass `max_bytes` (precompute_estimate.hpp). The factor estimate may
// be off by a few tens of percent: past 1.5x the limit it is refused here;
// Cholesky::factor checks the exact size after its own symbolic analysis.
void check_estimate(const mesh::TetMesh& m, const Model& M, const Partition& p, double max_bytes) {
  const auto mib = [](double b) { return (long long)(b / (1 << 20)); };
  const auto refuse = [&](const char* what, double bytes) {
    fail("hybrid precompute: ", what, " of the ", p.nonoperational_tets.size(), " nonoperational tets (",
         M.nonop_nodes.size(), " free nodes) would take about ", mib(bytes), " MiB, more than the ", mib(max_bytes),
         " MiB allowed (the sandbox's memory budget); use a coarser mesh, or run with --trust");
  };
  const PrecomputeEstimate counts = estimate_precompute(m, p, M.nonop_nodes, false);
  if (counts.assembly_bytes > max_bytes) refuse("assembling the stiffness", counts.assembly_bytes);
  const PrecomputeEstimate est = estimate_precompute(m, p, M.nonop_nodes, true);
  if (est.factor_bytes > 1.5 * max_bytes) refuse("the Cholesky factor of K22", est.factor_bytes);
}

}  // namespace

Model setup_model(const mesh::TetMesh& m, const std::vector<fem::Material>& tet_material, const Partition& p,
                  const PrecomputeOptions& opt) {
  const int nn = m.num_nodes();
  if (int(tet_material.size()) != m.num_tets())
    fail("hybrid precompute: ", tet_material.size(), " materials for ", m.num_tets(), " tets");
  if (p.num_nodes() != nn || int(p.operational_tet.size()) != m.num_tets())
    fail("hybrid precompute: the partition was made for another mesh (", p.num_nodes(), " nodes, ",
         p.operational_tet.size(), " tets; this mesh has ", nn, " nodes, ", m.num_tets(), " tets)");
  if (opt.block_columns < 1) fail("hybrid precompute: block_columns must be >= 1, got ", opt.block_columns);

  Model M;
  M.num_nodes = nn;
  M.partition = p;
  M.tet_material = tet_material;
  M.node_fixed.assign(size_t(nn), 0);
  M.node_nonoperational.assign(size_t(nn), 0);
  for (int v = 0; v < nn; ++v) {
    const NodeSet s = p.node_set[size_t(v)];
    M.node_fixed[size_t(v)] = s == NodeSet::fixed;
    M.node_nonoperational[size_t(v)] = s == NodeSet::surface || s == NodeSet::interior;
  }
  M.nonop_nodes = p.surface;
  M.nonop_nodes.insert(M.nonop_nodes.end(), p.interior.begin(), p.interior.end());
  M.surface_index = node_positions(p.surface, nn);

  // Initial loads: checked like per-frame loads (no interior, fixed or unknown nodes).
  // The initial strains' forces are added after the check: they may load interior nodes.
  M.initial_loads = Eigen::MatrixX3d::Zero(nn, 3);
  if (opt.initial_loads.size() > 0) {
    if (opt.initial_loads.rows() != nn)
      fail("hybrid precompute: initial_loads has ", opt.initial_loads.rows(), " rows for ", nn, " nodes");
    for (int v = 0; v < nn; ++v)
      if (opt.initial_loads.row(v).squaredNorm() != 0 || !opt.initial_loads.row(v).allFinite())
        check_load(p, v, opt.initial_loads.row(v).transpose(), "initial load");
    M.initial_loads = opt.initial_loads;
  }
  // Initial strains of the nonoperational tets: constant forces on s, i and I
  // (interior nodes too: condensed into the constant term below, DESIGN.md
  // "Initial strain"); the operational tets' share is the operational
  // system's (it changes when a cut splits them). Fixed rows go into the support.
  if (!p.nonoperational_tets.empty() && fem::any_element_load(tet_material)) {
    Eigen::MatrixX3d f0 = fem::element_loads(m, tet_material, p.nonoperational_tets);
    for (int v : p.fixed) f0.row(v).setZero();
    M.initial_loads += f0;
  }
  M.Ps0 = gather_nodes(M.initial_loads, p.surface);
  M.Pi0 = gather_nodes(M.initial_loads, p.interior);

  return M;
}

void build_operational(const mesh::TetMesh& m, Model& M) {
  M.operational = std::make_shared<const OperationalSystem>(
      build_operational_system(m, M.tet_material, M.partition.operational_tets, M.partition.interface, M.node_fixed,
                               M.node_nonoperational, M.K_prime));
}

Model precompute(const mesh::TetMesh& m, const std::vector<fem::Material>& tet_material, const Partition& p,
                 const PrecomputeOptions& opt) {
  Timer total;
  Model M = setup_model(m, tet_material, p, opt);
  const Eigen::Index ns3 = 3 * Eigen::Index(p.surface.size()), ni3 = 3 * Eigen::Index(p.interface.size());
  const Eigen::Index n23 = 3 * Eigen::Index(M.nonop_nodes.size());
  const Eigen::Index B = opt.block_columns;

  // Memory of each storage mode and of the assembly, from counts alone,
  // before anything large is allocated (the mode's blocks; K^non and its
  // blocks; the K22 factor from the node graph's symbolic analysis).
  // Solve temporaries: column blocks of n23 rows, B wide; factor mode solves
  // no blocks (K' comes from one bordered factorization), only a few columns
  // at a time later (a frame's update, a node's first touch). Counting B
  // columns there refused a 2M-tet body as "needs 2009 MiB ... make the
  // operational region's border smaller" when it had no border at all.
  const double temp = 8.0 * double(n23) * double(std::min<Eigen::Index>(B, std::max(ns3, ni3)));
  M.memory.dense_bytes = 8.0 * double(ns3 * ns3 + 2 * ns3 * ni3 + ni3 * ni3) + temp;
  M.memory.product_bytes = 8.0 * double(ns3 * ni3 + ni3 * ni3) + temp;
  M.memory.factor_bytes = 8.0 * double(ni3 * ni3) + 8.0 * double(n23) * 3;
  M.memory.budget_bytes = opt.memory_budget_bytes;
  auto check_fits = [&](Storage s) {
    const double need = s == Storage::dense     ? M.memory.dense_bytes
                        : s == Storage::product ? M.memory.product_bytes
                                                : M.memory.factor_bytes;
    if (need > opt.max_bytes)
      fail("hybrid precompute: storage mode '", to_string(s), "' needs about ", int(need / (1 << 20)), " MiB (",
           ns3 / 3, " surface and ", ni3 / 3, " interface nodes), more than the ", int(opt.max_bytes / (1 << 20)),
           " MiB allowed (the sandbox's memory budget); ", s != Storage::factor ? "use solver mode 'factor' or 'auto', " : "",
           "make the operational region's border smaller, or run with --trust");
  };
  if (opt.storage != Storage::automatic) check_fits(opt.storage);
  else check_fits(Storage::factor);
  if (std::isfinite(opt.max_bytes)) check_estimate(m, M, p, opt.max_bytes);
  opt.stop.poll("hybrid precompute");

  // Blocks of K^non.
  Timer t;
  Eigen::MatrixXd K_prime = Eigen::MatrixXd::Zero(ni3, ni3);
  SparseMatrix K22;
  if (!p.nonoperational_tets.empty()) {
    const SparseMatrix Knon = fem::assemble_stiffness(m, tet_material, p.nonoperational_tets, 0, &opt.stop);
    K22 = node_block(Knon, M.nonop_nodes, M.nonop_nodes);
    M.K2I = node_block(Knon, M.nonop_nodes, p.interface);
    M.KI2 = M.K2I.transpose();
    K_prime = Eigen::MatrixXd(node_block(Knon, p.interface, p.interface));
  } else {
    M.K2I = SparseMatrix(n23, ni3);
    M.KI2 = SparseMatrix(ni3, n23);
  }
  M.timings.assemble_ms = t.ms();
  opt.stop.poll("hybrid precompute");

  t.reset();
  if (n23 > 0) M.K22.factor(K22, "hybrid precompute: K22 (free nonoperational nodes)", opt.max_bytes);
  M.timings.factor_ms = t.ms();
  M.memory.factor_nonzeros = M.K22.factor_nonzeros();
  opt.stop.poll("hybrid precompute");

  // automatic: the cheaper full-surface update that fits (see the header).
  const bool product_fits = ns3 * ni3 > 0 && M.memory.product_bytes <= std::min(opt.memory_budget_bytes, opt.max_bytes);
  M.storage = opt.storage != Storage::automatic ? opt.storage
              : product_fits && 8.0 * double(ns3 * ni3) <= 24.0 * M.memory.factor_nonzeros ? Storage::product
                                                                                          : Storage::factor;
  const bool dense = M.storage == Storage::dense, keep_Y = M.has_Kstar_inv_Pstar();

  // Two blocks in flight when there are two idle cores and the second
  // block's temporary memory fits beside the chosen storage.
  const double need = dense ? M.memory.dense_bytes : keep_Y ? M.memory.product_bytes : M.memory.factor_bytes;
  const int block_threads =
      opt.block_threads > 0 ? std::min(opt.block_threads, 2)
      : thread_policy().threads >= 2 && need + temp <= std::min(opt.memory_budget_bytes, opt.max_bytes) ? 2
                                                                                                        : 1;

  // Y = K22^-1 K2I in column blocks: K' -= KI2 Y, K*^-1 P* = -Y[s, :].
  if (keep_Y) M.Kstar_inv_Pstar.resize(ns3, ni3);
  double pstar_ms = 0;
  std::mutex pstar_mu;
  t.reset();
  if (!keep_Y && n23 > 0 && ni3 > 0) {
    // Only K' is needed: one factorisation of the bordered matrix, no 3|I| solves.
    K_prime = schur_complement(K22, M.K2I, K_prime, "hybrid precompute: nonoperational region with interface");
  }
  if (keep_Y && n23 > 0)
    for_column_blocks(ni3, B, block_threads, [&](Eigen::Index c0, Eigen::Index w, solve::SolveWorkspace& ws) {
      opt.stop.poll("hybrid precompute (K22^-1 K2I)");
      const Eigen::MatrixXd Yb = M.K22.solve(Eigen::MatrixXd(M.K2I.middleCols(c0, w)), ws);
      K_prime.middleCols(c0, w).noalias() -= M.KI2 * Yb;  // (each block its own columns)
      Timer tp;
      M.Kstar_inv_Pstar.middleCols(c0, w) = -Yb.topRows(ns3);
      std::lock_guard lk(pstar_mu);
      pstar_ms += tp.ms();
    });
  K_prime = 0.5 * (K_prime + K_prime.transpose()).eval();  // symmetric to the last bit: CG and CHOLMOD agree
  M.K_prime = std::make_shared<const Eigen::MatrixXd>(std::move(K_prime));
  M.timings.K_prime_ms = t.ms() - pstar_ms;
  M.timings.Kstar_inv_Pstar_ms = pstar_ms;

  if (dense) {
    t.reset();
    M.KI2_K22inv_s = -M.Kstar_inv_Pstar.transpose();
    M.timings.KI2_K22inv_ms = t.ms();

    // K*^-1 = (K22^-1)_ss: unit right-hand sides on the surface DOFs (the first 3|s| rows).
    t.reset();
    M.Kstar_inv.resize(ns3, ns3);
    for_column_blocks(ns3, B, block_threads, [&](Eigen::Index c0, Eigen::Index w, solve::SolveWorkspace& ws) {
      opt.stop.poll("hybrid precompute (K*^-1)");
      Eigen::MatrixXd E = Eigen::MatrixXd::Zero(n23, w);
      for (Eigen::Index k = 0; k < w; ++k) E(c0 + k, k) = 1.0;
      M.Kstar_inv.middleCols(c0, w) = M.K22.solve(E, ws).topRows(ns3);
    });
    M.timings.Kstar_inv_ms = t.ms();
  }
  // The constant term: K*^-1 Ps0 and P' for the initial loads. With loads on
  // interior nodes (initial strains) it is (K22^-1 P2)[s] and KI2 K22^-1 P2,
  // P2 = [Ps0; Pi0], one solve; surface loads alone use the dense blocks.
  t.reset();
  if (M.storage == Storage::dense && M.Pi0.squaredNorm() == 0) {
    M.Kstar_inv_Ps0 = M.Kstar_inv * M.Ps0;
    M.P_prime0 = M.KI2_K22inv_s * M.Ps0;
  } else {
    Eigen::VectorXd z = Eigen::VectorXd::Zero(n23);
    if (n23 > 0 && (M.Ps0.squaredNorm() > 0 || M.Pi0.squaredNorm() > 0)) {
      Eigen::VectorXd P2(n23);
      P2 << M.Ps0, M.Pi0;
      solve::SolveWorkspace ws;
      z = M.K22.solve(P2, ws).col(0);
    }
    M.Kstar_inv_Ps0 = z.head(ns3);
    M.P_prime0 = M.KI2 * z;
  }
  M.timings.Kstar_inv_Ps0_ms = t.ms();

  opt.stop.poll("hybrid precompute");
  t.reset();
  build_operational(m, M);
  M.timings.operational_ms = t.ms();
  M.timings.total_ms = total.ms();
  return M;
}

std::shared_ptr<const OperationalSystem> rebuild_operational_system(
    const Model& model, const mesh::TetMesh& m, const std::vector<fem::Material>& tet_material,
    const std::vector<int>& operational_tets, const std::vector<char>& new_fixed, const OperationalSystem* before,
    fem::ReassemblyReport* report) {
  if (m.num_nodes() < model.num_nodes)
    fail("rebuild operational system: the mesh has ", m.num_nodes(), " nodes, fewer than the ", model.num_nodes,
         " of the precomputed model; cutting may only append nodes");
  if (int(tet_material.size()) != m.num_tets())
    fail("rebuild operational system: ", tet_material.size(), " materials for ", m.num_tets(), " tets");
  if (!new_fixed.empty() && int(new_fixed.size()) != m.num_nodes())
    fail("rebuild operational system: the fixed mask has ", new_fixed.size(), " entries for ", m.num_nodes(),
         " nodes");
  return std::make_shared<const OperationalSystem>(
      build_operational_system(m, tet_material, operational_tets, model.partition.interface,
                               new_fixed.empty() ? model.node_fixed : new_fixed, model.node_nonoperational,
                               model.K_prime, before, report));
}

std::string describe(const Model& M) {
  const auto& T = M.timings;
  return cat("hybrid model: ", describe(M.partition.counts), "; storage ", to_string(M.storage), " (dense blocks ",
             M.memory.dense_bytes / 1048576.0, " MiB, product mode ", M.memory.product_bytes / 1048576.0,
             " MiB, factor mode ", M.memory.factor_bytes / 1048576.0, " MiB, K22 factor ",
             M.memory.factor_nonzeros, " nonzeros, budget ", M.memory.budget_bytes / 1048576.0, " MiB); precompute ms: assemble ", T.assemble_ms,
             ", factor K22 ", T.factor_ms, ", K' ", T.K_prime_ms, ", KI2 K22^-1 ", T.KI2_K22inv_ms, ", K*^-1 ",
             T.Kstar_inv_ms, ", K*^-1 P* ", T.Kstar_inv_Pstar_ms, ", K*^-1 Ps0 ", T.Kstar_inv_Ps0_ms,
             ", operational system ", T.operational_ms, ", total ", T.total_ms);
}

}  // namespace softcut::hybrid
