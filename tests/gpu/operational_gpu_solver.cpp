#include "gpu/operational_gpu_solver.hpp"

#include <doctest/doctest.h>

#include <random>

#include "../hybrid/fixtures.hpp"
#include "fem/whole_mesh.hpp"
#include "hybrid/update.hpp"

using namespace softcut;

namespace {

gl::EglContext& context() {
  static gl::EglContext ctx;
  return ctx;
}

std::vector<int> visible_nodes(const hybrid::Partition& p) {
  std::vector<int> v = p.operational;
  v.insert(v.end(), p.interface.begin(), p.interface.end());
  v.insert(v.end(), p.surface.begin(), p.surface.end());
  return v;
}

}  // namespace

TEST_SUITE("gpu/operational_gpu_solver") {
  TEST_CASE("the device solve gives the CPU hybrid answer and the monolithic one") {
    std::mt19937 rng(77);
    int with_operational = 0;
    for (int trial = 0; trial < 4; ++trial) {  // one per partition kind: llvmpipe is slow
      const auto c = test::random_case(rng, trial % 4);
      const hybrid::Model model = hybrid::precompute(c.mesh, c.material, c.partition);
      solve::CgOptions tight;
      tight.tolerance = 1e-12;
      hybrid::State cpu = hybrid::make_state(model, std::make_unique<hybrid::CgSolver>(tight));
      gpu::ComputeCgOptions go;
      go.tolerance = 1e-12;
      hybrid::State dev = hybrid::make_state(model, std::make_unique<gpu::OperationalGpuSolver>(context(), go));
      for (int frame = 0; frame < 3; ++frame) {
        const auto loads = test::random_loads(c.partition, rng, 3);
        hybrid::update(model, cpu, loads);
        hybrid::update(model, dev, loads);
        const Eigen::MatrixX3d ref =
            fem::solve_whole_mesh(c.mesh, c.material, c.fixed_mask, test::load_field(c.mesh.num_nodes(), loads));
        INFO("trial ", trial, " frame ", frame, " ", hybrid::describe(c.partition.counts));
        CHECK(test::relative_error(dev.u, cpu.u, visible_nodes(c.partition)) <= 1e-9);
        CHECK(test::relative_error(dev.u, ref, visible_nodes(c.partition)) <= 1e-8);
      }
      with_operational += model.operational->size() > 0;
    }
    CHECK(with_operational >= 2);
  }
}
