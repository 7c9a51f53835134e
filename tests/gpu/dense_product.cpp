#include "gpu/dense_product.hpp"

#include <doctest/doctest.h>

#include <future>
#include <random>
#include <thread>
#include <vector>

#define GL_GLEXT_PROTOTYPES 1
#include <GL/glcorearb.h>

#include "../hybrid/fixtures.hpp"
#include "fem/whole_mesh.hpp"
#include "hybrid/update.hpp"

using namespace softcut;

namespace {

gl::EglContext& context() {
  static gl::EglContext ctx;
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

  TEST_CASE("a product destroyed while its context is current on another thread deletes nothing elsewhere") {
    // A run state dropped on a thread that cannot take the product's context,
    // with another context current there: the product's buffers stay with
    // their context, and no buffer of the current one is deleted in their name.
    auto dev = std::make_unique<gpu::DeviceDenseProduct>(context(), Eigen::MatrixXd::Ones(5, 2));
    context().release_current();
    std::promise<void> holding, done;
    std::thread other([&] {
      context().make_current();
      holding.set_value();
      done.get_future().wait();
      context().release_current();
    });
    holding.get_future().wait();
    {
      gl::EglContext second;  // current here; its buffer names start at 1, as the first context's did
      second.make_current();
      std::vector<gpu::StorageBuffer> mine(4096);
      for (auto& b : mine) b.allocate(16);
      CHECK_THROWS_AS(context().make_current(), Error);  // current on `other`
      CHECK_NOTHROW(dev.reset());
      second.make_current();
      int alive = 0;
      for (std::uint32_t id = 1; id <= 4096; ++id) alive += glIsBuffer(id) == GL_TRUE;
      CHECK(alive == 4096);
    }
    done.set_value();
    other.join();
    context().make_current();
    gpu::DeviceDenseProduct again(context(), Eigen::MatrixXd::Ones(5, 2));
    Eigen::VectorXd y;
    again.apply(Eigen::VectorXd::Ones(2), y);
    CHECK(y.isApproxToConstant(2.0));
  }

  TEST_CASE("a wrong AI size is an error") {
    gpu::DeviceDenseProduct dev(context(), Eigen::MatrixXd::Ones(4, 3));
    Eigen::VectorXd y;
    CHECK_THROWS_AS(dev.apply(Eigen::VectorXd::Ones(2), y), Error);
  }
}
