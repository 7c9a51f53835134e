#include "gpu/compute_cg.hpp"

#include <doctest/doctest.h>

#include <random>

#include "cut/cutter.hpp"
#include "fem/assembly.hpp"
#include "fem/dof_map.hpp"
#include "hybrid/partition.hpp"
#include "hybrid/precompute.hpp"
#include "mesh/generate/box.hpp"
#include "random_block_system.hpp"
#include "solve/cholesky.hpp"

namespace {

// A CHOLMOD solve of A x = b (the reference).
Eigen::VectorXd direct_solve(const Eigen::SparseMatrix<double>& A, const Eigen::VectorXd& b) {
  softcut::solve::SolveWorkspace ws;
  return softcut::solve::Cholesky(A).solve(b, ws);
}


softcut::gl::EglContext& context() {
  static softcut::gl::EglContext ctx;  // one context for the suite (llvmpipe here)
  return ctx;
}

Eigen::SparseMatrix<double> box_stiffness(int nx, int ny, int nz, double jitter, unsigned seed) {
  softcut::mesh::BoxOptions o;
  o.nx = nx;
  o.ny = ny;
  o.nz = nz;
  o.max_corner = {0.1 * nx / nz, 0.1 * ny / nz, 0.1};
  o.jitter = jitter;
  o.seed = seed;
  const auto m = softcut::mesh::generate_box(o);
  const std::vector<softcut::fem::Material> mats(size_t(m.num_tets()), {3e3, 0.45});
  std::vector<char> free(size_t(m.num_nodes()), 1);
  for (int i = 0; i < m.num_nodes(); ++i) free[size_t(i)] = m.nodes(i, 0) > 1e-12;
  return softcut::fem::restrict_matrix(softcut::fem::assemble_stiffness(m, mats), softcut::fem::make_dof_map(free));
}

// The device copy must be the host system in device precision.
void check_device_copy(const softcut::gpu::ComputeCg& cg, const softcut::gpu::BlockSystem& s, bool fp64) {
  const auto d = cg.device_system();
  auto device = [fp64](std::vector<double> v) {
    if (!fp64)
      for (double& x : v) x = double(float(x));
    return v;
  };
  CHECK(d.row_ptr == s.row_ptr);
  CHECK(d.col == s.col);
  CHECK(d.values == device(s.values));
  CHECK(d.diag_inverse == device(s.diag_inverse));
  CHECK(d.dense == device(s.dense));
}

}  // namespace

TEST_SUITE("gpu/compute_cg") {
  TEST_CASE("fp32 kernels with fp64 refinement meet the CPU tolerance on several meshes") {
    int mesh_index = 0;
    for (auto [nx, ny, nz] : {std::array{4, 2, 2}, std::array{6, 3, 2}, std::array{8, 3, 3}}) {
      const auto K = box_stiffness(nx, ny, nz, 0.15, unsigned(++mesh_index));
      Eigen::MatrixXd D = Eigen::MatrixXd::Zero(6, 6);  // a K'-like SPD corner on the last two nodes
      D.diagonal().setConstant(50.0);
      D(0, 3) = D(3, 0) = -20.0;
      const auto bs = softcut::gpu::make_block_system(K, &D);
      Eigen::SparseMatrix<double> A = K;
      for (int i = 0; i < 6; ++i)
        for (int j = 0; j < 6; ++j)
          if (D(i, j) != 0) A.coeffRef(K.rows() - 6 + i, K.rows() - 6 + j) += D(i, j);
      const Eigen::VectorXd b = Eigen::VectorXd::Random(K.rows());
      const Eigen::VectorXd direct = direct_solve(A, b);

      softcut::gpu::ComputeCg cg(context(), {});
      cg.set_system(bs);
      Eigen::VectorXd x;
      const auto rep = cg.solve([&](const Eigen::VectorXd& v, Eigen::VectorXd& y) { bs.apply(v, y); }, b, x);
      CAPTURE(mesh_index);
      CHECK(rep.converged);
      CHECK(rep.relative_residual <= 1e-10);
      CHECK(rep.refinements >= 2);  // fp32 alone cannot reach 1e-10: the refinement did the rest
      CHECK((x - direct).norm() <= 1e-7 * direct.norm());
    }
  }

  TEST_CASE("fp64 kernels converge in one refinement") {
    const auto K = box_stiffness(5, 2, 2, 0.1, 9);
    const auto bs = softcut::gpu::make_block_system(K);
    softcut::gpu::ComputeCgOptions opt;
    opt.fp64 = true;
    softcut::gpu::ComputeCg cg(context(), opt);
    cg.set_system(bs);
    const Eigen::VectorXd b = Eigen::VectorXd::Random(K.rows());
    Eigen::VectorXd x;
    const auto rep = cg.solve([&](const Eigen::VectorXd& v, Eigen::VectorXd& y) { bs.apply(v, y); }, b, x);
    CHECK(rep.converged);
    CHECK(rep.refinements == 1);
    const Eigen::VectorXd direct = direct_solve(K, b);
    CHECK((x - direct).norm() <= 1e-8 * direct.norm());
  }

  TEST_CASE("warm start from the solution needs no device iteration") {
    const auto K = box_stiffness(4, 2, 2, 0.1, 3);
    const auto bs = softcut::gpu::make_block_system(K);
    softcut::gpu::ComputeCg cg(context(), {});
    cg.set_system(bs);
    const Eigen::VectorXd b = Eigen::VectorXd::Random(K.rows());
    Eigen::VectorXd x = direct_solve(K, b);
    const auto rep = cg.solve([&](const Eigen::VectorXd& v, Eigen::VectorXd& y) { bs.apply(v, y); }, b, x);
    CHECK(rep.converged);
    CHECK(rep.iterations == 0);
  }

  TEST_CASE("an unchanged pattern re-uploads only the changed blocks") {
    const auto K = box_stiffness(6, 3, 3, 0.1, 4);
    auto bs = softcut::gpu::make_block_system(K);
    softcut::gpu::ComputeCg cg(context(), {});
    const std::size_t full = cg.set_system(bs);
    CHECK(cg.set_system(bs) == 0);
    // Stiffen one node (as a local re-assembly after a cut would): same pattern.
    Eigen::SparseMatrix<double> K2 = K;
    for (int c = 0; c < 3; ++c) K2.coeffRef(15 + c, 15 + c) *= 2;
    const auto bs2 = softcut::gpu::make_block_system(K2);
    const std::size_t partial = cg.set_system(bs2);
    CHECK(partial > 0);
    CHECK(partial * 50 < full);
    const Eigen::VectorXd b = Eigen::VectorXd::Random(K.rows());
    Eigen::VectorXd x, expected;
    const auto rep = cg.solve([&](const Eigen::VectorXd& v, Eigen::VectorXd& y) { bs2.apply(v, y); }, b, x);
    CHECK(rep.converged);
    // The device used the new values: its answer satisfies the new system.
    bs2.apply(x, expected);
    CHECK((expected - b).norm() <= 1e-10 * b.norm());
  }

  TEST_CASE("the answer scales with the load: tiny and huge right-hand sides converge in fp32") {
    // fp32 dot products of a residual of 1e-14 N underflow (r.z ~ 1e-32 and
    // below), and those of 1e20 N overflow; the solve is linear, so x(s b) = s x(b).
    const auto K = box_stiffness(4, 2, 2, 0.1, 5);
    const auto bs = softcut::gpu::make_block_system(K);
    const Eigen::VectorXd b = Eigen::VectorXd::Random(K.rows());
    const Eigen::VectorXd direct = direct_solve(K, b);
    softcut::gpu::ComputeCg cg(context(), {});
    cg.set_system(bs);
    for (double scale : {1e-14, 1e20}) {
      Eigen::VectorXd x;
      const auto rep =
          cg.solve([&](const Eigen::VectorXd& v, Eigen::VectorXd& y) { bs.apply(v, y); }, scale * b, x);
      CAPTURE(scale);
      CHECK(rep.converged);
      CHECK(rep.relative_residual <= 1e-10);
      CHECK((x - scale * direct).norm() <= 1e-7 * scale * direct.norm());
    }
  }

  TEST_CASE("a residual check interval below 1 is refused, not a division by zero") {
    const auto K = box_stiffness(3, 2, 2, 0.0, 1);
    const auto bs = softcut::gpu::make_block_system(K);
    softcut::gpu::ComputeCgOptions opt;
    opt.check_every = 0;
    softcut::gpu::ComputeCg cg(context(), opt);
    cg.set_system(bs);
    const Eigen::VectorXd b = Eigen::VectorXd::Ones(K.rows());
    Eigen::VectorXd x;
    CHECK_THROWS_WITH_AS(cg.solve([&](const Eigen::VectorXd& v, Eigen::VectorXd& y) { bs.apply(v, y); }, b, x),
                         doctest::Contains("check_every"), softcut::Error);
  }

  TEST_CASE("NaN right-hand sides are refused") {
    const auto K = box_stiffness(3, 2, 2, 0.0, 1);
    const auto bs = softcut::gpu::make_block_system(K);
    softcut::gpu::ComputeCg cg(context(), {});
    cg.set_system(bs);
    Eigen::VectorXd b = Eigen::VectorXd::Ones(K.rows());
    b(3) = std::nan("");
    Eigen::VectorXd x;
    CHECK_THROWS_AS(cg.solve([&](const Eigen::VectorXd& v, Eigen::VectorXd& y) { bs.apply(v, y); }, b, x),
                    softcut::Error);
  }

  TEST_CASE("rows inserted, appended and removed: the device copy and its products equal the host system") {
    std::mt19937 rng(11);
    for (bool fp64 : {true, false}) {
      softcut::gpu::ComputeCgOptions opt;
      opt.fp64 = fp64;
      softcut::gpu::ComputeCg cg(context(), opt);
      softcut::test::NodeGraph g = softcut::test::random_graph(rng, 60, 3);
      cg.set_system(softcut::test::block_system(g));
      int incremental = 0, reallocated = 0, moved = 0;
      for (int edit = 0; edit < 15; ++edit) {
        const int kind = edit % 5, count = 1 + int(rng() % 5);
        const int free_nodes = g.num_nodes - g.dense_nodes;
        const int at = kind == 1 ? free_nodes : int(rng() % unsigned(free_nodes - count));
        if (kind == 3) softcut::test::remove_nodes(g, at, count);
        else if (kind == 4) softcut::test::insert_nodes(g, rng, g.num_nodes, 1);  // after the rest: rows stay put
        else softcut::test::insert_nodes(g, rng, at, kind == 2 ? 12 * count : count);  // kind 2: a big growth
        const auto s = softcut::test::block_system(g);
        const std::size_t sent = cg.set_system(s);
        const auto& up = cg.last_upload();
        CAPTURE(fp64);
        CAPTURE(edit);
        CHECK(sent == up.sent_bytes);
        CHECK(sent <= up.full_bytes);
        if (kind != 3) CHECK(up.incremental);  // removed nodes' edges reach anywhere: may be a full upload
        incremental += up.incremental;
        reallocated += up.reallocated;
        moved += up.moved_bytes > 0;
        // Appending after every row moves only the rows after the new node's neighbours.
        if (kind == 4 && !up.reallocated) CHECK(up.moved_bytes * 10 < up.full_bytes);
        check_device_copy(cg, s, fp64);
        const Eigen::VectorXd x = Eigen::VectorXd::Random(s.size());
        Eigen::VectorXd y_host, y_device;
        s.apply(x, y_host);
        cg.apply_device(x, y_device);
        CHECK((y_device - y_host).norm() <= (fp64 ? 1e-13 : 1e-6) * y_host.norm());
      }
      CHECK(incremental >= 12);
      CHECK(reallocated >= 1);
      CHECK(moved >= 8);
    }
  }

  TEST_CASE("after a real cut the device copy is updated incrementally and solves the cut system") {
    using namespace softcut;
    mesh::BoxOptions o;
    o.nx = 8, o.ny = 4, o.nz = 3;
    o.max_corner = {0.16, 0.08, 0.06};
    const mesh::TetMesh m0 = mesh::generate_box(o);
    const std::vector<fem::Material> mat0(size_t(m0.num_tets()), {3e3, 0.45});
    std::vector<int> fixed;
    for (int v = 0; v < m0.num_nodes(); ++v)
      if (m0.nodes(v, 0) < 1e-12) fixed.push_back(v);
    const auto part = hybrid::make_partition(m0, hybrid::tets_in_box(m0, {0.059, -1, -1}, {1, 1, 1}), fixed);
    const hybrid::Model model = hybrid::precompute(m0, mat0, part);
    std::vector<char> locked(size_t(m0.num_nodes()), 0);
    for (int v : part.interface) locked[size_t(v)] = 1;
    mesh::TetMesh m = m0;
    cut::CutState cs = cut::make_cut_state(m, part.operational_tet, locked);
    std::vector<fem::Material> mat = mat0;
    std::vector<char> op_mask = part.operational_tet;
    std::shared_ptr<const hybrid::OperationalSystem> sys = model.operational;
    gpu::ComputeCg cg(context(), {});
    cg.set_system(gpu::make_block_system(sys->K, sys->K_prime.get()));
    // Two steps of a short blade along z, between grid planes in x, entering the body along y.
    for (double y : {0.025, 0.045}) {
      const cut::CutRecord rec = cut::cut_step(
          m, cs, cut::sweep_segment({0.115, y - 0.035, 0.03}, {0.115, y - 0.035, 0.05}, {0.115, y, 0.03}, {0.115, y, 0.05}));
      REQUIRE(!rec.new_nodes.empty());
      std::vector<fem::Material> mat_after;
      std::vector<char> op_after;
      std::vector<int> op;
      for (int t = 0; t < m.num_tets(); ++t) {
        mat_after.push_back(mat[size_t(rec.tet_parent[size_t(t)])]);
        op_after.push_back(op_mask[size_t(rec.tet_parent[size_t(t)])]);
        if (op_after.back()) op.push_back(t);
      }
      mat = std::move(mat_after);
      op_mask = std::move(op_after);
      const auto before = gpu::make_block_system(sys->K, sys->K_prime.get());
      const auto next = hybrid::rebuild_operational_system(model, m, mat, op);
      CHECK(next->num_operational > sys->num_operational);  // cut nodes appended to set 1
      REQUIRE(next->num_interface > 0);
      const auto bs = gpu::make_block_system(next->K, next->K_prime.get());
      const std::size_t sent = cg.set_system(bs);
      const auto up = cg.last_upload();
      MESSAGE("cut step: ", rec.new_nodes.size(), " nodes added, ", before.num_blocks, " -> ", bs.num_blocks,
              " block rows; sent ", sent, " B (moved on the device ", up.moved_bytes, " B), a full upload sends ",
              up.full_bytes, " B");
      CHECK(up.incremental);
      CHECK(sent * 5 < up.full_bytes);
      check_device_copy(cg, bs, false);
      sys = next;
    }
    const hybrid::OperationalSystem* sys1 = sys.get();
    const Eigen::VectorXd b = Eigen::VectorXd::Random(sys1->size());
    const Eigen::VectorXd direct = direct_solve(sys1->assembled(), b);
    Eigen::VectorXd x;
    const auto rep = cg.solve([&](const Eigen::VectorXd& v, Eigen::VectorXd& y) { sys1->apply(v, y); }, b, x);
    CHECK(rep.converged);
    CHECK(rep.relative_residual <= cg.options().tolerance);
    CHECK((x - direct).norm() <= 1e-7 * direct.norm());
  }
}
