#include "gpu/dense_product.hpp"

#include <doctest/doctest.h>

#include <random>

#include "../hybrid/fixtures.hpp"
#include "fem/whole_mesh.hpp"
#include "hybrid/update.hpp"

using namespace softcut;

namespace {

gpu::EglContext& context() {
  static gpu::EglContext ctx;
  return ctx;
}

}  // namespace

TEST_SUITE("gpu/dense_product") {
  TEST_CASE("the device product equals the CPU product in double precision") {
    std::mt19937 rng(3);
    std::normal_distribution<double> g;
    for (const auto& rc : {std::array{1, 1}, std::array{70, 9}, std::array{301, 45}}) {
      const int r = rc[0], c = rc[1];  // not a structured binding: CAPTURE makes a lambda (clang 14)
      Eigen::MatrixXd M(r, c);
      for (Eigen::Index i = 0; i < M.size(); ++i) M.data()[i] = g(rng);
      Eigen::VectorXd x(c);
      for (Eigen::Index i = 0; i < x.size(); ++i) x(i) = g(rng);
      gpu::DeviceDenseProduct dev(context(), M);
      Eigen::VectorXd y;
      dev.apply(x, y);
      const Eigen::VectorXd ref = M * x;
      CAPTURE(r);
      CHECK((y - ref).norm() <= 1e-13 * ref.norm());
    }
  }

  TEST_CASE("hybrid frames with the device product match the monolithic solve") {
    std::mt19937 rng(41);
    int used = 0;
    for (int trial = 0; trial < 6; ++trial) {
      const auto c = test::random_case(rng, trial % 4);
      hybrid::PrecomputeOptions po;
      po.storage = hybrid::Storage::dense;
      const hybrid::Model model = hybrid::precompute(c.mesh, c.material, c.partition, po);
      if (model.ni() == 0 || model.ns() == 0) continue;
      solve::CgOptions tight;
      tight.tolerance = 1e-13;
      hybrid::State state = hybrid::make_state(model, std::make_unique<hybrid::CgSolver>(tight));
      state.nonoperational_product = std::make_shared<gpu::DeviceDenseProduct>(context(), model.Kstar_inv_Pstar);
      ++used;
      for (int frame = 0; frame < 2; ++frame) {
        const auto loads = test::random_loads(c.partition, rng, 3);
        hybrid::update(model, state, loads);
        const Eigen::MatrixX3d ref =
            fem::solve_whole_mesh(c.mesh, c.material, c.fixed_mask, test::load_field(c.mesh.num_nodes(), loads));
        CHECK(test::relative_error(state.u, ref, c.partition.surface) <= 1e-8);
      }
    }
    CHECK(used >= 2);
  }

  TEST_CASE("a wrong AI size is an error") {
    gpu::DeviceDenseProduct dev(context(), Eigen::MatrixXd::Ones(4, 3));
    Eigen::VectorXd y;
    CHECK_THROWS_AS(dev.apply(Eigen::VectorXd::Ones(2), y), Error);
  }
}
