#include "hybrid/update.hpp"

#include <algorithm>
#include <optional>

#include "core/error.hpp"
#include "core/threads.hpp"
#include "core/timer.hpp"

namespace softcut::hybrid {

namespace {

// P2 = [Ps0 + Ps_interact; Pi0] on the K22 DOFs (surface first), minus K2I AI.
Eigen::VectorXd nonoperational_rhs(const Model& M, const State& S, const Eigen::VectorXd* AI) {
  Eigen::VectorXd P2(3 * Eigen::Index(M.nonop_nodes.size()));
  P2 << M.Ps0 + S.Ps_interact, M.Pi0;
  if (AI && AI->size() > 0) P2.noalias() -= M.K2I * *AI;
  return P2;
}

void scatter_interior(const Model& M, const Eigen::VectorXd& w, State& S) {
  const auto& interior = M.partition.interior;
  const Eigen::Index off = 3 * Eigen::Index(M.ns());
  for (size_t k = 0; k < interior.size(); ++k)
    S.u.row(interior[k]) = w.segment<3>(off + 3 * Eigen::Index(k)).transpose();
}

// out = A x in two fixed row halves (A column-major: each half streams its
// rows of every column; the product is bandwidth-bound), the second on the
// helper thread when there is one. Same halves either way: same bits.
void product_rows(const Eigen::MatrixXd& A, const Eigen::VectorXd& x, Eigen::VectorXd& out, HelperThread* helper) {
  out.resize(A.rows());
  row_halves(helper, A.rows(), [&](Eigen::Index r0, Eigen::Index rows) {
    out.segment(r0, rows).noalias() = A.middleRows(r0, rows) * x;
  });
}

}  // namespace

State make_state(const Model& M, std::unique_ptr<OperationalSolver> solver, const StateOptions& opt) {
  State S;
  S.u = Eigen::MatrixX3d::Zero(M.num_nodes, 3);
  S.operational = M.operational;
  S.solver = solver ? std::move(solver) : std::make_unique<CgSolver>();
  S.Ps_interact = Eigen::VectorXd::Zero(3 * Eigen::Index(M.ns()));
  S.As_loads = M.Kstar_inv_Ps0;
  S.P_prime = M.P_prime0;
  S.forces = M.initial_loads;
  S.slot.assign(size_t(M.ns()), -1);
  if (M.storage != Storage::dense && M.ns() > 0)
    S.columns = std::make_unique<ColumnCache>(M, opt.column_cache_bytes);
  // A second thread pays for the frame's dense products, and for a first
  // touch's backward solve through the K22 factor, once they are past the
  // caches' fastest level (kHelperMinEntries); it needs an idle core.
  const double n_op = M.operational ? M.operational->size() : 0;
  // A nonlinear law's tets count as kEntriesPerNonlinearTet entries each
  // (an element pass with its tangent reads and writes about that many).
  const double nonlinear_tets =
      M.operational && M.operational->nonlinear_law ? double(M.operational->nonlinear->size()) : 0.0;
  const double dense_entries = double(M.Kstar_inv_Pstar.size()) +
                               (n_op <= CholmodSolver::kDenseMax ? n_op * n_op : 0.0) +
                               (S.columns ? M.K22.factor_nonzeros() : 0.0) + kEntriesPerNonlinearTet * nonlinear_tets;
  const int threads = opt.product_threads > 0 ? opt.product_threads
                      : dense_entries >= kHelperMinEntries ? std::min(2, thread_policy().threads)
                                                           : 1;
  if (threads >= 2) {
    S.helper = std::make_shared<HelperThread>();
    S.solver->share_helper(S.helper);
    if (S.columns) S.columns->share_helper(S.helper);
  }
  return S;
}

void prefetch_columns(const Model& M, State& S, std::span<const int> nodes) {
  if (!S.columns) return;
  std::vector<int> pos;
  for (int v : nodes)
    if (v >= 0 && v < M.num_nodes && M.surface_index[size_t(v)] >= 0) pos.push_back(M.surface_index[size_t(v)]);
  S.columns->prefetch(pos);
}

void set_operational_system(State& S, std::shared_ptr<const OperationalSystem> sys) {
  if (!sys) fail("set_operational_system: no system given");
  S.operational = std::move(sys);
}

const FrameReport& update(const Model& M, State& S, std::span<const Load> loads, const UpdateOptions& opt) {
  return update(M, S, loads, *S.solver, opt);
}

const FrameReport& update(const Model& M, State& S, std::span<const Load> loads, OperationalSolver& solver,
                          const UpdateOptions& opt) {
  Timer total, t;
  FrameReport rep;
  // With a helper thread, OpenBLAS stays on one thread through the frame:
  // after a two-thread call its worker spins on the helper's core for a
  // while, and the helper's halves (stage 5, a first touch's subtrees) then
  // crawl (a 3-column backward solve: helper took 1 of 11 subtrees, no
  // faster than one thread; with BLAS on one thread 10 of 11, 1.5x faster).
  std::optional<SingleThreadedBlas> one_blas_thread;
  if (S.helper) {
    one_blas_thread.emplace();
    S.helper->wake();  // spinning by the time stages 4 and 5 come
  }
  const OperationalSystem& op = *S.operational;
  const int nn_op = int(op.node_index.size());
  if (S.u.rows() < nn_op) {  // nodes appended by cutting
    const Eigen::Index old = S.u.rows();
    S.u.conservativeResize(nn_op, 3);
    S.forces.conservativeResize(nn_op, 3);
    S.u.bottomRows(nn_op - old).setZero();
    S.forces.bottomRows(nn_op - old).setZero();
  }

  // Stage 2: check every load before touching the state.
  for (const Load& L : loads) {
    NodeSet set;
    if (L.node >= M.num_nodes && L.node < nn_op) {
      if (!L.force.allFinite()) fail("load on node ", L.node, ": the force has NaN or Inf components");
      set = NodeSet::operational;
    } else {
      set = check_load(M.partition, L.node, L.force, "load");
    }
    if (set != NodeSet::surface && op.node_index[size_t(L.node)] < 0)
      fail("load on node ", L.node, ": the node is no longer part of the operational mesh (removed by cutting?)");
  }
  S.pending.clear();
  S.loaded_operational.clear();
  for (const Load& L : loads) {
    const int pos = L.node < M.num_nodes ? M.surface_index[size_t(L.node)] : -1;
    if (pos >= 0) {
      int& slot = S.slot[size_t(pos)];
      if (slot < 0) {
        slot = int(S.pending.size());
        S.pending.emplace_back(pos, L.force);
      } else {
        S.pending[size_t(slot)].second += L.force;
      }
    } else {
      S.forces.row(L.node) += L.force.transpose();
      S.loaded_operational.push_back(L.node);
    }
  }
  rep.loaded_operational_nodes = int(S.loaded_operational.size());
  rep.loads_ms = t.ms();

  // Stage 3: selective multiplication on the changed surface loads.
  t.reset();
  const bool dense = M.storage == Storage::dense;
  auto apply_change = [&](int pos, const Eigen::Vector3d& delta) {
    ++rep.loaded_surface_nodes;
    if (dense) {
      S.As_loads.noalias() += M.Kstar_inv.middleCols<3>(3 * Eigen::Index(pos)) * delta;
      if (M.ni() > 0) S.P_prime.noalias() += M.KI2_K22inv_s.middleCols<3>(3 * Eigen::Index(pos)) * delta;
    } else {
      const std::shared_ptr<const NodeColumns> c = S.columns->get(pos);
      S.As_loads.noalias() += c->Kstar_inv * delta;
      if (M.ni() > 0) S.P_prime.noalias() += c->KI2_K22inv * delta;
    }
  };
  if (!dense && S.columns) {  // first touches of this frame in one solve (columns.hpp)
    std::vector<int>& need = S.touched;
    need.clear();
    for (int pos : S.loaded_surface)
      if (S.slot[size_t(pos)] < 0) need.push_back(pos);
    for (const auto& [pos, f] : S.pending)
      if ((f - S.Ps_interact.segment<3>(3 * Eigen::Index(pos))).squaredNorm() > 0) need.push_back(pos);
    S.columns->ensure(need);
  }
  for (int pos : S.loaded_surface)
    if (S.slot[size_t(pos)] < 0) {
      auto old = S.Ps_interact.segment<3>(3 * Eigen::Index(pos));
      apply_change(pos, -old);
      old.setZero();
    }
  S.loaded_surface.clear();
  for (const auto& [pos, f] : S.pending) {
    auto old = S.Ps_interact.segment<3>(3 * Eigen::Index(pos));
    const Eigen::Vector3d delta = f - old;
    if (delta.squaredNorm() > 0) apply_change(pos, delta);
    old = f;
    if (f.squaredNorm() > 0) S.loaded_surface.push_back(pos);
    S.slot[size_t(pos)] = -1;
  }
  rep.selective_ms = t.ms();

  // Stage 4: operational solve, warm-started.
  t.reset();
  if (S.x_generation != op.generation) {
    S.x_operational = gather_nodes(S.u, op.nodes);
    S.secant.clear();
    S.x_generation = op.generation;
  }
  const Eigen::VectorXd b = op.rhs(S.forces, S.P_prime);
  for (int v : S.loaded_operational)  // back to the initial loads before anything can throw
    S.forces.row(v) = v < M.num_nodes ? Eigen::RowVector3d(M.initial_loads.row(v)) : Eigen::RowVector3d::Zero();
  static const NonlinearFrame linear_frame;
  const NonlinearFrame& nl = opt.nonlinear ? *opt.nonlinear : linear_frame;
  if (needs_nonlinear_solve(op, nl)) {
    rep.newton = true;
    const Eigen::VectorXd x_last = S.x_operational;
    rep.nonlinear = solve_nonlinear(op, b, S.x_operational, solver, S.nonlinear, nl, "operational solve",
                                    S.secant.predict(S.x_operational), S.helper.get());
    S.secant.record(x_last, S.x_operational);
    rep.solve.iterations = rep.nonlinear.newton.cg_iterations;
    rep.solve.relative_residual = rep.nonlinear.newton.relative_residual;
  } else {
    rep.solve = solver.solve(op, b, S.x_operational);
    S.secant.clear();  // a linear frame keeps no history (no copy a frame on the fast path)
  }
  scatter_nodes(S.x_operational, op.nodes, S.u);
  rep.operational_ms = t.ms();

  // Stage 5: nonoperational surface.
  t.reset();
  const Eigen::Index ni3 = 3 * Eigen::Index(M.ni());
  const Eigen::VectorXd AI = S.x_operational.tail(ni3);
  if (!opt.full_surface) {
    // Rows of the loaded nodes and the asked-for ones: 3 rows of K*^-1 P*,
    // which is -(KI2 K22^-1 columns of the node)^T (K22 is symmetric).
    auto write = [&](int pos) {
      const Eigen::Index r = 3 * Eigen::Index(pos);
      Eigen::Vector3d a = S.As_loads.segment<3>(r);
      if (ni3 > 0) {
        if (M.has_Kstar_inv_Pstar()) a.noalias() += M.Kstar_inv_Pstar.middleRows<3>(r) * AI;
        else a.noalias() -= S.columns->get(pos)->KI2_K22inv.transpose() * AI;
      }
      S.u.row(M.partition.surface[size_t(pos)]) = a.transpose();
      ++rep.surface_nodes_updated;
    };
    for (int pos : S.loaded_surface) write(pos);
    for (int v : opt.surface_nodes)
      if (v >= 0 && v < M.num_nodes && M.surface_index[size_t(v)] >= 0) write(M.surface_index[size_t(v)]);
    if (opt.recover_interior) recover_interior(M, S);
  } else if (M.has_Kstar_inv_Pstar()) {
    Eigen::VectorXd As = S.As_loads;
    if (ni3 > 0 && S.nonoperational_product) {
      Eigen::VectorXd prod;
      S.nonoperational_product->apply(AI, prod);
      As += prod;
    } else if (ni3 > 0) {
      Eigen::VectorXd prod;
      product_rows(M.Kstar_inv_Pstar, AI, prod, S.helper.get());
      As += prod;
    }
    scatter_nodes(As, M.partition.surface, S.u);
    if (opt.recover_interior) recover_interior(M, S);
  } else if (!M.nonop_nodes.empty()) {
    const Eigen::VectorXd w = M.K22.solve(nonoperational_rhs(M, S, &AI), *S.ws).col(0);
    scatter_nodes(w.head(3 * Eigen::Index(M.ns())), M.partition.surface, S.u);
    if (opt.recover_interior) scatter_interior(M, w, S);
  }
  if (opt.full_surface) rep.surface_nodes_updated = M.ns();
  rep.surface_complete = opt.full_surface;
  rep.interior_recovered = opt.recover_interior;
  rep.nonoperational_ms = t.ms();
  rep.total_ms = total.ms();
  ++S.frames;
  S.last = rep;
  return S.last;
}

void recover_interior(const Model& M, State& S) {
  if (M.nonop_nodes.empty()) return;
  const Eigen::VectorXd AI = gather_nodes(S.u, M.partition.interface);
  scatter_interior(M, M.K22.solve(nonoperational_rhs(M, S, &AI), *S.ws).col(0), S);
}

}  // namespace softcut::hybrid
