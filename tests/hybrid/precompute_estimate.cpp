#include "hybrid/precompute_estimate.hpp"

#include <doctest/doctest.h>

#include <atomic>
#include <chrono>
#include <random>
#include <thread>

#include "core/stop_flags.hpp"
#include "fem/assembly.hpp"
#include "fixtures.hpp"
#include "hybrid/node_blocks.hpp"
#include "hybrid/precompute.hpp"
#include "solve/cholesky.hpp"

using namespace softcut;
using namespace softcut::hybrid;

namespace {

std::vector<int> nonop_order(const Partition& p) {
  std::vector<int> n = p.surface;
  n.insert(n.end(), p.interior.begin(), p.interior.end());
  return n;
}

}  // namespace

TEST_SUITE("hybrid/precompute_estimate") {
  TEST_CASE("the counts are the assembled matrices' nonzeros, exactly, for every kind of partition") {
    std::mt19937 rng(7);
    for (int trial = 0; trial < 36; ++trial) {
      const test::HybridCase c = test::random_case(rng, trial % 6, 5);
      const Partition& p = c.partition;
      CAPTURE(trial);
      const std::vector<int> order = nonop_order(p);
      const PrecomputeEstimate e = estimate_precompute(c.mesh, p, order, false);
      if (p.nonoperational_tets.empty()) {
        CHECK(e.knon_nonzeros == 0);
        continue;
      }
      const SparseMatrix Knon = fem::assemble_stiffness(c.mesh, c.material, p.nonoperational_tets);
      CHECK(e.knon_nonzeros == double(Knon.nonZeros()));
      CHECK(e.k22_nonzeros == double(node_block(Knon, order, order).nonZeros()));
      CHECK(e.k2I_nonzeros == double(node_block(Knon, order, p.interface).nonZeros()));
      CHECK(e.assembly_bytes > 12 * e.knon_nonzeros);
      CHECK(e.factor_nonzeros == 0);  // not asked for
    }
  }

  TEST_CASE("the factor estimate from the node graph is close to the K22 factor CHOLMOD makes") {
    for (int nx : {6, 12, 24}) {
      CAPTURE(nx);
      const test::HybridCase c = test::supernodal_case(nx, fem::Material{5e3, 0.45});
      const Partition& p = c.partition;
      const std::vector<int> order = nonop_order(p);
      const PrecomputeEstimate e = estimate_precompute(c.mesh, p, order, true);
      const SparseMatrix Knon = fem::assemble_stiffness(c.mesh, c.material, p.nonoperational_tets);
      solve::Cholesky K22;
      K22.factor(node_block(Knon, order, order));
      const double ratio = e.factor_nonzeros / K22.factor_nonzeros();
      INFO("estimate ", e.factor_nonzeros, ", factor ", K22.factor_nonzeros());
      CHECK(ratio > 0.75);
      CHECK(ratio < 1.33);
      CHECK(e.factor_bytes == 16 * e.factor_nonzeros);
    }
  }

  TEST_CASE("precompute refuses, before assembling, a model over its byte limit - naming what and how much") {
    const test::HybridCase c = test::supernodal_case(24, fem::Material{5e3, 0.45});
    PrecomputeOptions opt;
    opt.storage = Storage::factor;
    const PrecomputeEstimate e = estimate_precompute(c.mesh, c.partition, nonop_order(c.partition), true);
    opt.max_bytes = 0.9 * e.assembly_bytes;
    std::string msg;
    try {
      precompute(c.mesh, c.material, c.partition, opt);
    } catch (const Error& err) {
      msg = err.what();
    }
    CHECK(msg.find("hybrid precompute: assembling the stiffness of the") == 0);
    CHECK(msg.find("MiB allowed") != std::string::npos);
    // Room for the assembly but not for 1.5x the factor's estimate: the factor.
    opt.max_bytes = std::max(e.assembly_bytes, e.factor_bytes / 2);
    if (e.factor_bytes > 1.5 * opt.max_bytes) {
      msg.clear();
      try {
        precompute(c.mesh, c.material, c.partition, opt);
      } catch (const Error& err) {
        msg = err.what();
      }
      CHECK(msg.find("hybrid precompute: the Cholesky factor of K22") == 0);
    }
    // Within the limit: the same model as without one.
    opt.max_bytes = 4 * (e.assembly_bytes + e.factor_bytes);
    const Model limited = precompute(c.mesh, c.material, c.partition, opt);
    opt.max_bytes = std::numeric_limits<double>::infinity();
    const Model free = precompute(c.mesh, c.material, c.partition, opt);
    CHECK(*limited.K_prime == *free.K_prime);
  }

  TEST_CASE("a stop request ends the precompute promptly, with InterruptedError or TimeoutError") {
    const test::HybridCase c = test::supernodal_case(24, fem::Material{5e3, 0.45});
    std::atomic<bool> interrupt{true}, deadline{false};
    PrecomputeOptions opt;
    opt.storage = Storage::dense;
    opt.block_columns = 16;  // many column blocks: a poll between each
    opt.stop = StopFlags{&interrupt, &deadline};
    CHECK_THROWS_AS(precompute(c.mesh, c.material, c.partition, opt), InterruptedError);
    interrupt = false, deadline = true;
    CHECK_THROWS_AS(precompute(c.mesh, c.material, c.partition, opt), TimeoutError);
    // Set while the column blocks are being solved: ends before the rest.
    deadline = false;
    const auto t0 = std::chrono::steady_clock::now();
    const Model full = precompute(c.mesh, c.material, c.partition, opt);
    const double whole = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    std::thread stopper([&] {
      std::this_thread::sleep_for(std::chrono::duration<double>(whole / 3));
      interrupt = true;
    });
    const auto t1 = std::chrono::steady_clock::now();
    CHECK_THROWS_AS(precompute(c.mesh, c.material, c.partition, opt), InterruptedError);
    const double stopped = std::chrono::duration<double>(std::chrono::steady_clock::now() - t1).count();
    stopper.join();
    INFO("whole ", whole, " s, stopped after ", stopped, " s");
    CHECK(stopped < 0.8 * whole);
    // The assembly polls too.
    interrupt = true;
    CHECK_THROWS_AS(fem::assemble_stiffness(c.mesh, c.material, {}, 1, &opt.stop), InterruptedError);
    CHECK_THROWS_AS(fem::assemble_stiffness(c.mesh, c.material, {}, 2, &opt.stop), InterruptedError);
    interrupt = false;
    CHECK(fem::assemble_stiffness(c.mesh, c.material, {}, 2, &opt.stop).nonZeros() > 0);
  }
}
