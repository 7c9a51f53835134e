#include "gpu/compute_cg.hpp"

#include <doctest/doctest.h>

#include "fem/assembly.hpp"
#include "fem/dof_map.hpp"
#include "mesh/generate/box.hpp"
#include "solve/cholesky.hpp"

namespace {

softcut::gpu::EglContext& context() {
  static softcut::gpu::EglContext ctx;  // one context for the suite (llvmpipe here)
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
      const Eigen::VectorXd direct = softcut::solve::Cholesky(A).solve(b);

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
    const Eigen::VectorXd direct = softcut::solve::Cholesky(K).solve(b);
    CHECK((x - direct).norm() <= 1e-8 * direct.norm());
  }

  TEST_CASE("warm start from the solution needs no device iteration") {
    const auto K = box_stiffness(4, 2, 2, 0.1, 3);
    const auto bs = softcut::gpu::make_block_system(K);
    softcut::gpu::ComputeCg cg(context(), {});
    cg.set_system(bs);
    const Eigen::VectorXd b = Eigen::VectorXd::Random(K.rows());
    Eigen::VectorXd x = softcut::solve::Cholesky(K).solve(b);
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
    const Eigen::VectorXd direct = softcut::solve::Cholesky(K).solve(b);
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
}
