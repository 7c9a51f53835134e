#include "backend/solver.hpp"

#include "backend/hybrid_solver.hpp"

#include <doctest/doctest.h>

#include <cmath>

#include "core/error.hpp"
#include "core/timer.hpp"
#include "sim/fixtures.hpp"
#include "gpu/dense_product.hpp"
#include "gl/egl_context.hpp"
#include "sim/step.hpp"
#include "test_support.hpp"

using V = Eigen::Vector3d;
namespace backend = softcut::backend;
namespace sim = softcut::sim;
namespace tools = softcut::tools;
using softcut::Error;

namespace {

// One context for the suite (llvmpipe on CI machines); outlives every Model.
softcut::gl::EglContext& context() {
  static softcut::gl::EglContext ctx;
  return ctx;
}

// The cantilever with a grasper pulling its top middle up over the frames.
sim::ScenarioSpec gpu_spec(const std::string& backend) {
  auto spec = softcut::test::cantilever_spec(softcut::test::scratch_dir("sim_solver_" + backend), 0.4, 0.02);
  spec.solver.backend = backend::parse_backend(backend);
  spec.solver.cg_tolerance = 1e-10;
  const V p(0.07, 0.01, 0.02);
  spec.tools.push_back(softcut::test::spring_grasper(20.0, 0.011, tools::Path::polyline({0.0, 0.4}, {p, p + V(0, 0.002, 0.004)})));
  return spec;
}

// The cantilever without tools, loaded from frame 0, 2 frames, compiled for
// backend cpu and for backend gpu (fp32 kernels) in the suite's context.
std::pair<sim::Model, sim::Model> loaded_cpu_and_gpu_models() {
  auto spec = gpu_spec("cpu");
  spec.tools.clear();
  spec.loads[0].magnitude = tools::Ramp::linear_ramp(0.01, 0.02, 0.0, 1.0);  // nonzero from frame 0
  spec.timeline.duration = 0.1;                                              // 2 frames
  sim::Model cpu = sim::compile(spec);
  spec.solver.backend = backend::Backend::gpu;
  return {std::move(cpu), sim::compile(spec, backend::RunResources{&context()})};
}

}  // namespace

TEST_SUITE("backend/solver") {
  TEST_CASE("unit responses of operational nodes come in one batch equal to whole updates and to the monolithic solve") {
    // Nodes of the operational box (x in [0.04, 0.06]) and one on the
    // nonoperational surface: with the surface node the hybrid solver takes
    // every column through a whole update, without it one batch.
    for (const std::string storage : {"product", "factor"})
      for (const bool vtu : {false, true}) {  // vtu: interior rows wanted too
        CAPTURE(storage);
        CAPTURE(vtu);
        auto spec = softcut::test::cantilever_spec(softcut::test::scratch_dir("sim_solver_units"));
        spec.solver.mode = softcut::hybrid::parse_storage(storage);
        spec.outputs.vtu = vtu;
        const sim::Model m = sim::compile(spec);
        spec.solver.backend = backend::Backend::monolithic;
        const sim::Model mono = sim::compile(spec);
        std::vector<int> op, all;
        for (int n = 0; n < m.mesh.num_nodes(); ++n) {
          const auto set = m.partition.node_set[size_t(n)];
          if ((set == softcut::hybrid::NodeSet::operational || set == softcut::hybrid::NodeSet::interface) && op.size() < 4)
            op.push_back(n);
        }
        REQUIRE(op.size() == 4);
        REQUIRE_FALSE(m.partition.surface.empty());
        all = op;
        all.push_back(m.partition.surface.front());
        backend::SolverRun run, run_all, run_mono;
        m.solver->start_run(run, nullptr);
        m.solver->start_run(run_all, nullptr);
        mono.solver->start_run(run_mono, nullptr);
        Eigen::MatrixXd R, R_all, R_mono;
        m.solver->unit_responses(op, run, R);
        m.solver->unit_responses(all, run_all, R_all);
        mono.solver->unit_responses(op, run_mono, R_mono);
        REQUIRE(R.cols() == 12);
        REQUIRE(R.rows() == R_all.rows());
        const Eigen::MatrixXd R_loop = R_all.leftCols(12);
        CHECK((R - R_loop).norm() <= 1e-12 * R_loop.norm());
        // Against the whole-mesh solve on every node the hybrid solver reports
        // (interior rows only when wanted; they stay zero otherwise).
        for (int n = 0; n < m.mesh.num_nodes(); ++n) {
          const bool interior = m.partition.node_set[size_t(n)] == softcut::hybrid::NodeSet::interior;
          if (interior && !vtu) CHECK(R.middleRows<3>(3 * n).norm() == 0);
          else CHECK((R.middleRows<3>(3 * n) - R_mono.middleRows<3>(3 * n)).norm() <= 1e-9 * R_mono.norm());
        }
      }
  }

  TEST_CASE("a solve whose residual is not small is an error, never a result") {
    CHECK_NOTHROW(backend::check_solve_residual(0.0, "x"));
    CHECK_NOTHROW(backend::check_solve_residual(backend::kMaxRelativeResidual, "x"));
    CHECK_THROWS_WITH_AS(backend::check_solve_residual(1e-6, "operational solve"),
                         doctest::Contains("operational solve: the relative residual of the solve is 1e-06"), Error);
    CHECK_THROWS_AS(backend::check_solve_residual(std::nan(""), "x"), Error);
    CHECK_THROWS_AS(backend::check_solve_residual(INFINITY, "x"), Error);
  }

  TEST_CASE("backend choice without a context: auto gives the CPU's CHOLMOD and gpu is an error naming the fix") {
    backend::SolverSpec s;
    s.backend = backend::Backend::automatic;
    const backend::BackendChoice a = backend::choose_backend(s, nullptr);
    CHECK(a.backend == backend::Backend::direct);
    CHECK(a.requested == backend::Backend::automatic);
    CHECK(a.reason.find("CHOLMOD") != std::string::npos);
    s.backend = backend::Backend::gpu;
    CHECK_THROWS_WITH_AS(backend::choose_backend(s, nullptr), doctest::Contains("--backend cpu"), Error);
    for (backend::Backend b : {backend::Backend::cpu, backend::Backend::direct, backend::Backend::monolithic}) {
      s.backend = b;
      CHECK(backend::choose_backend(s, nullptr).backend == b);
    }
    auto spec = gpu_spec("gpu");
    CHECK_THROWS_WITH_AS(sim::compile(spec), doctest::Contains("backend 'gpu' needs an OpenGL context"), Error);
  }

  TEST_CASE("auto never picks llvmpipe: it stays on the CPU's CHOLMOD, stage 5 too, and says why") {
    const softcut::gl::ContextInfo& info = context().info();
    backend::SolverSpec s;
    s.backend = backend::Backend::automatic;
    const backend::BackendChoice c = backend::choose_backend(s, &context().info());
    CHECK(c.backend == backend::Backend::direct);
    CHECK(c.device.find(info.renderer) == 0);
    CHECK(c.reason.find("CHOLMOD") != std::string::npos);
    CHECK(c.device_product == !info.software);
    const sim::Model m = sim::compile(gpu_spec("auto"), backend::RunResources{&context()});
    CHECK(m.solver->backend().backend == c.backend);
    CHECK_FALSE(m.solver->backend().device_product);  // llvmpipe; and the cantilever's block is small
  }

  TEST_CASE("auto on a hardware GPU: CHOLMOD (measured faster than GPU CG there) with stage 5 on the device") {
    softcut::gl::ContextInfo h100;
    h100.renderer = "NVIDIA H100 80GB HBM3/PCIe/SSE2";
    h100.compute = true;
    backend::SolverSpec s;
    s.backend = backend::Backend::automatic;
    backend::BackendChoice c = backend::choose_backend(s, &h100);
    CHECK(c.backend == backend::Backend::direct);
    CHECK(c.device_product);
    CHECK(c.device_product_min_entries == softcut::gpu::DeviceDenseProduct::kWorthwhileEntries);
    CHECK(c.reason.find("measured faster than GPU CG") != std::string::npos);
    CHECK(c.device == h100.renderer);
    h100.compute = false;  // no compute shaders: nothing on the device
    CHECK_FALSE(backend::choose_backend(s, &h100).device_product);
    s.backend = backend::Backend::direct;  // asked for: the CPU only
    h100.compute = true;
    CHECK_FALSE(backend::choose_backend(s, &h100).device_product);
  }

  TEST_CASE("the direct backend with stage 5 on the device solves like the direct backend on the CPU") {
    // What auto builds on a hardware GPU, here on llvmpipe with the size
    // threshold lowered so the small model's dense block goes to the device.
    if (!context().info().compute) {
      MESSAGE("no compute shaders in this context: the device product is not testable here");
      return;
    }
    auto spec = gpu_spec("direct");
    spec.solver.mode = softcut::hybrid::Storage::dense;  // K*^-1 P* kept dense
    const sim::Model cpu = sim::compile(spec);
    REQUIRE(cpu.solver->name().find("on the device") == std::string::npos);
    backend::BackendChoice c = backend::choose_backend(spec.solver, &context().info());
    c.device_product = true;
    c.device_product_min_entries = 0;
    const std::unique_ptr<backend::Solver> dev =
        backend::make_hybrid_solver(cpu.mesh, cpu.tet_material, cpu.partition, spec.solver, false, c, &context());
    CHECK(dev->name().find("operational cholmod; (K*^-1 P*) AI on the device") != std::string::npos);
    // The solver says it uses the context (softcut run then draws frames on this thread).
    CHECK(dev->backend().device_product);
    CHECK(dev->backend().reason.ends_with("; (K*^-1 P*) AI on the GPU"));
    c.device_product_min_entries = 1e12;  // allowed, but no block is that large: not used
    CHECK_FALSE(
        backend::make_hybrid_solver(cpu.mesh, cpu.tet_material, cpu.partition, spec.solver, false, c, &context())
            ->backend()
            .device_product);
    backend::SolverRun ra, rb;
    backend::SolveStats sa, sb;
    for (int f = 0; f < 3; ++f) {
      CAPTURE(f);
      Eigen::MatrixX3d forces = Eigen::MatrixX3d::Zero(cpu.mesh.num_nodes(), 3);
      for (int v : cpu.surface.nodes)
        if (cpu.partition.node_set[size_t(v)] != softcut::hybrid::NodeSet::fixed)
          forces.row(v) = V(0.01 * (f + 1), -0.02, 0.003 * (v % 7));
      Eigen::MatrixX3d ua, ub;
      cpu.solver->solve(forces, ua, ra, sa);
      dev->solve(forces, ub, rb, sb);
      const double scale = ua.cwiseAbs().maxCoeff();
      REQUIRE(scale > 0);
      double diff = 0;
      for (int v = 0; v < cpu.mesh.num_nodes(); ++v)
        if (cpu.partition.node_set[size_t(v)] != softcut::hybrid::NodeSet::interior)
          diff = std::max(diff, (ua.row(v) - ub.row(v)).cwiseAbs().maxCoeff());
      CHECK(diff <= 1e-12 * scale);  // the same fp64 product, summed in another order
    }
  }

  // llvmpipe runs a CG iteration in milliseconds (dispatch overhead), so
  // these use few frames and one grasped node.
  TEST_CASE("backend gpu (fp32 kernels + fp64 refinement) steps like backend cpu") {
    if (!context().info().compute) {
      MESSAGE("no compute shaders in this context: GPU backend not testable here");
      return;
    }
    const auto [cpu, gpu] = loaded_cpu_and_gpu_models();
    CHECK(gpu.solver->backend().backend == backend::Backend::gpu);
    CHECK(!gpu.solver->backend().gpu_fp64);
    CHECK(gpu.solver->name().find("gpu cg, fp32") != std::string::npos);
    sim::State a = sim::make_state(cpu), b = sim::make_state(gpu);
    for (int f = 0; f < gpu.num_frames; ++f) {
      CAPTURE(f);
      sim::step(cpu, a);
      sim::step(gpu, b);
      // Both meet the relative residual 1e-10 of the same operational system.
      const double scale = a.displacement.cwiseAbs().maxCoeff();
      REQUIRE(scale > 0);
      CHECK((a.displacement - b.displacement).cwiseAbs().maxCoeff() <= 1e-8 * scale);
      CHECK(b.last_cg_iterations > 0);
    }
    CHECK(b.stats.max_relative_residual <= 1e-10);
  }

  TEST_CASE("backend gpu: two runs of one Model interleaved keep their own device buffers and warm starts") {
    if (!context().info().compute) {
      MESSAGE("no compute shaders in this context: GPU backend not testable here");
      return;
    }
    const auto [cpu, gpu] = loaded_cpu_and_gpu_models();
    sim::State a1 = sim::make_state(cpu), a2 = sim::make_state(cpu);
    sim::State b1 = sim::make_state(gpu), b2 = sim::make_state(gpu);
    a2.loads[0].scale = b2.loads[0].scale = -3.0;  // the second run pulls the other way
    for (int f = 0; f < gpu.num_frames; ++f) {
      CAPTURE(f);
      sim::step(gpu, b1);
      sim::step(gpu, b2);
      sim::step(cpu, a1);
      sim::step(cpu, a2);
      const double scale = a2.displacement.cwiseAbs().maxCoeff();
      REQUIRE(scale > 0);
      CHECK((a1.displacement - b1.displacement).cwiseAbs().maxCoeff() <= 1e-8 * scale);
      CHECK((a2.displacement - b2.displacement).cwiseAbs().maxCoeff() <= 1e-8 * scale);
    }
  }

  TEST_CASE("backend gpu with fp64 kernels: implicit grasper springs through the device equal cpu") {
    if (!context().info().compute) {
      MESSAGE("no compute shaders in this context: GPU backend not testable here");
      return;
    }
    auto spec = gpu_spec("cpu");
    spec.tools[0].radius = 0.005;  // one node: 3 unit-load solves on the device
    spec.tools[0].path = tools::Path::polyline({0.0, 0.1}, {V(0.08, 0.01, 0.02), V(0.08, 0.012, 0.024)});
    spec.timeline.duration = 0.1;  // 2 frames
    spec.loads[0].magnitude = tools::Ramp::linear_ramp(0.01, 0.02, 0.0, 1.0);  // the spring resists from frame 0
    const sim::Model cpu = sim::compile(spec);
    spec.solver.backend = backend::Backend::gpu;
    spec.solver.gpu_fp64 = true;
    sim::Model gpu = [&] {
      try {
        return sim::compile(spec, backend::RunResources{&context()});
      } catch (const Error& e) {
        return sim::Model{};  // a device without fp64 kernels: said below
      }
    }();
    if (!gpu.solver) {
      MESSAGE("fp64 compute kernels not available in this context");
      return;
    }
    CHECK(gpu.solver->backend().gpu_fp64);
    sim::State a = sim::make_state(cpu), b = sim::make_state(gpu);
    for (int f = 0; f < gpu.num_frames; ++f) {
      CAPTURE(f);
      sim::step(cpu, a);
      sim::step(gpu, b);
      REQUIRE(!b.tools[0].grip.empty());
      REQUIRE(b.tools[0].nodes == a.tools[0].nodes);
      const double scale = a.displacement.cwiseAbs().maxCoeff();
      REQUIRE(scale > 0);
      CHECK((a.displacement - b.displacement).cwiseAbs().maxCoeff() <= 1e-8 * scale);
      CHECK((a.tools[0].total_force - b.tools[0].total_force).norm() <= 1e-8 * a.tools[0].total_force.norm());
    }
    CHECK(b.springs.builds == 1);
    CHECK((a.springs.compliance - b.springs.compliance).norm() <= 1e-8 * a.springs.compliance.norm());
  }
}
