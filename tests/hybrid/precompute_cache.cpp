#include "hybrid/precompute_cache.hpp"

#include <doctest/doctest.h>
#include <fcntl.h>
#include <sys/file.h>
#include <unistd.h>

#include <chrono>
#include <filesystem>
#include <fstream>
#include <random>

#include "core/binary_io.hpp"
#include "core/checked_file.hpp"
#include "fixtures.hpp"
#include "hybrid/update.hpp"
#include "mesh/generate/box.hpp"

using namespace softcut;
using namespace softcut::hybrid;
using softcut::test::HybridCase;
namespace fs = std::filesystem;

namespace {

struct TempDir {
  fs::path path;
  TempDir() {
    path = fs::temp_directory_path() / ("softcut-cache-test-" + std::to_string(::getpid()) + "-" +
                                        std::to_string(std::random_device{}()));
    fs::create_directories(path);
  }
  ~TempDir() {
    std::error_code ec;
    fs::remove_all(path, ec);
  }
};

// Displacements of a few frames of random loads (with interior recovery), CHOLMOD backend.
Eigen::MatrixX3d run_frames(const Model& M, const HybridCase& c, unsigned seed) {
  std::mt19937 rng(seed);
  State S = make_state(M, std::make_unique<CholmodSolver>());
  UpdateOptions o;
  o.recover_interior = true;
  for (int f = 0; f < 3; ++f) update(M, S, test::random_loads(c.partition, rng, 3), o);
  return S.u;
}

void flip_byte(const fs::path& file, std::uintmax_t at) {
  std::fstream f(file, std::ios::in | std::ios::out | std::ios::binary);
  f.seekg(std::streamoff(at));
  char b = 0;
  f.read(&b, 1);
  b = char(b ^ 0x5a);
  f.seekp(std::streamoff(at));
  f.write(&b, 1);
}

}  // namespace

TEST_SUITE("hybrid/precompute_cache") {
  TEST_CASE("a cache hit gives the cold precompute's model bit for bit, in every storage mode") {
    std::mt19937 rng(31);
    int hits = 0;
    for (int trial = 0; trial < 12; ++trial) {
      TempDir dir;
      const HybridCase c = test::random_case(rng, trial % 6);
      PrecomputeOptions po;
      po.storage = std::array{Storage::automatic, Storage::dense, Storage::product, Storage::factor}[size_t(trial % 4)];
      if (trial % 5 == 1) po.initial_loads = test::load_field(c.mesh.num_nodes(), test::random_loads(c.partition, rng, 2));
      CacheReport r1, r2;
      const Model cold = precompute_cached(c.mesh, c.material, c.partition, po, {dir.path}, &r1);
      const Model warm = precompute_cached(c.mesh, c.material, c.partition, po, {dir.path}, &r2);
      INFO("trial ", trial, " ", describe(c.partition.counts), " storage ", to_string(cold.storage));
      CHECK(r1.enabled);
      CHECK(!r1.hit);
      CHECK(r1.miss_reason == "no entry");
      CHECK(r1.write_error == "");
      CHECK(fs::exists(r1.file));
      REQUIRE(r2.hit);
      CHECK(r2.key == r1.key);
      CHECK(warm.storage == cold.storage);
      CHECK(*warm.K_prime == *cold.K_prime);
      CHECK(warm.Kstar_inv == cold.Kstar_inv);
      CHECK(warm.Kstar_inv_Pstar == cold.Kstar_inv_Pstar);
      CHECK(warm.KI2_K22inv_s == cold.KI2_K22inv_s);
      CHECK(warm.Kstar_inv_Ps0 == cold.Kstar_inv_Ps0);
      CHECK(warm.P_prime0 == cold.P_prime0);
      CHECK(Eigen::MatrixXd(warm.K2I) == Eigen::MatrixXd(cold.K2I));
      CHECK(warm.memory.factor_nonzeros == cold.memory.factor_nonzeros);
      // The loaded factor solves exactly as the computed one: whole frames agree bit for bit.
      CHECK(run_frames(warm, c, 9) == run_frames(cold, c, 9));
      hits += r2.hit;
    }
    CHECK(hits == 12);
  }

  TEST_CASE("a supernodal K22 factor round-trips bit for bit") {
    const HybridCase c = test::supernodal_case(10, fem::Material{});
    const mesh::TetMesh& m = c.mesh;
    const Partition& p = c.partition;
    const std::vector<fem::Material>& mat = c.material;
    TempDir dir;
    CacheReport r1, r2;
    const Model cold = precompute_cached(m, mat, p, {}, {dir.path}, &r1);
    const Model warm = precompute_cached(m, mat, p, {}, {dir.path}, &r2);
    REQUIRE(r2.hit);
    Eigen::VectorXd b = Eigen::VectorXd::LinSpaced(cold.K22.rows(), -1.0, 2.0);
    solve::SolveWorkspace ws;
    CHECK(warm.K22.solve(b, ws) == cold.K22.solve(b, ws));
    // Supernodal: the saved factor's values are padded past its nonzeros.
    CHECK(cold.memory.factor_nonzeros > 1e5);
    State s1 = make_state(cold, std::make_unique<CholmodSolver>()), s2 = make_state(warm, std::make_unique<CholmodSolver>());
    const std::vector<Load> loads = {{p.surface[p.surface.size() / 2], Eigen::Vector3d(0.01, 0.0, -0.02)}};
    UpdateOptions o;
    o.recover_interior = true;
    update(cold, s1, loads, o);
    update(warm, s2, loads, o);
    CHECK(s1.u == s2.u);
  }

  TEST_CASE("a changed input is a miss, and a corrupt, truncated or foreign entry is rebuilt, never used") {
    std::mt19937 rng(32);
    HybridCase c = test::random_case(rng, 0);
    TempDir dir;
    CacheReport r;
    const Model cold = precompute_cached(c.mesh, c.material, c.partition, {}, {dir.path}, &r);
    const fs::path file = r.file;
    const Eigen::MatrixX3d truth = run_frames(cold, c, 4);

    // A changed material, a changed option: different keys, misses.
    std::vector<fem::Material> mat = c.material;
    mat[0].young *= 1.0000001;
    CacheReport rm;
    precompute_cached(c.mesh, mat, c.partition, {}, {dir.path}, &rm);
    CHECK(!rm.hit);
    CHECK(rm.key != r.key);
    mat = c.material;  // only an initial strain changed: its forces enter the cached constant term
    mat[0].initial_strain[1] = 1e-3;
    precompute_cached(c.mesh, mat, c.partition, {}, {dir.path}, &rm);
    CHECK(!rm.hit);
    PrecomputeOptions po;
    po.block_columns = 7;
    precompute_cached(c.mesh, c.material, c.partition, po, {dir.path}, &rm);
    CHECK(!rm.hit);

    // Same key, other inputs (a planted entry from another model): "inputs differ".
    const HybridCase other = test::random_case(rng, 0);
    CacheReport ro;
    precompute_cached(other.mesh, other.material, other.partition, {}, {dir.path}, &ro);
    fs::copy_file(ro.file, file, fs::copy_options::overwrite_existing);
    CacheReport rd;
    Model m = precompute_cached(c.mesh, c.material, c.partition, {}, {dir.path}, &rd);
    CHECK(!rd.hit);
    CHECK(rd.miss_reason == "inputs differ");
    CHECK(run_frames(m, c, 4) == truth);
    CHECK(precompute_cached(c.mesh, c.material, c.partition, {}, {dir.path}, &rd).storage == cold.storage);
    CHECK(rd.hit);  // rewritten

    // One flipped byte anywhere in the payload, or a cut file: rebuilt.
    const std::uintmax_t size = fs::file_size(file);
    int corrupt = 0;
    for (std::uintmax_t at : {size - 1, size - 20, size / 2, size * 3 / 4, std::uintmax_t(200)}) {
      flip_byte(file, at);
      CacheReport rc;
      m = precompute_cached(c.mesh, c.material, c.partition, {}, {dir.path}, &rc);
      INFO("byte ", at, " of ", size, ": ", rc.miss_reason);
      CHECK(!rc.hit);
      corrupt += rc.miss_reason.rfind("corrupt", 0) == 0 || rc.miss_reason == "inputs differ";
      CHECK(run_frames(m, c, 4) == truth);
      CHECK(fs::file_size(file) == size);  // rewritten whole
    }
    CHECK(corrupt == 5);
    fs::resize_file(file, size / 3);
    CacheReport rt;
    m = precompute_cached(c.mesh, c.material, c.partition, {}, {dir.path}, &rt);
    CHECK(rt.miss_reason.rfind("corrupt", 0) == 0);
    CHECK(run_frames(m, c, 4) == truth);
    {
      std::ofstream(file, std::ios::binary | std::ios::trunc) << "not a cache file at all";
    }
    m = precompute_cached(c.mesh, c.material, c.partition, {}, {dir.path}, &rt);
    CHECK(!rt.hit);
    CHECK(run_frames(m, c, 4) == truth);
    // A symlink where the entry should be is not followed.
    fs::remove(file);
    fs::create_symlink(ro.file, file);
    m = precompute_cached(c.mesh, c.material, c.partition, {}, {dir.path}, &rt);
    CHECK(rt.miss_reason == "not a regular file");
    CHECK(run_frames(m, c, 4) == truth);
  }

  TEST_CASE("the cache keeps within its size bound, dropping the least recently used entries") {
    std::mt19937 rng(33);
    TempDir dir;
    std::vector<HybridCase> cases;
    std::vector<CacheReport> reps(4);
    for (int k = 0; k < 4; ++k) cases.push_back(test::random_case(rng, 0));
    CacheOptions co{dir.path};
    for (int k = 0; k < 4; ++k) precompute_cached(cases[size_t(k)].mesh, cases[size_t(k)].material, cases[size_t(k)].partition, {}, co, &reps[size_t(k)]);
    double largest = 0;
    for (const auto& r : reps) largest = std::max(largest, r.bytes);
    co.max_bytes = 2.5 * largest;  // room for two entries
    CacheReport again;
    precompute_cached(cases[0].mesh, cases[0].material, cases[0].partition, {}, co, &again);  // hit: now most recent
    CHECK(again.hit);
    const HybridCase fresh = test::random_case(rng, 0);
    CacheReport rf;
    precompute_cached(fresh.mesh, fresh.material, fresh.partition, {}, co, &rf);
    CHECK(rf.evicted >= 2);
    double total = 0;
    for (const auto& e : fs::directory_iterator(dir.path)) total += double(e.file_size());
    CHECK(total <= co.max_bytes);
    CHECK(fs::exists(rf.file));
  }

  TEST_CASE("temporary files of killed writes are counted and removed - a live writer's stays") {
    std::mt19937 rng(35);
    TempDir dir;
    const HybridCase c = test::random_case(rng, 0);
    auto plant = [&](const std::string& name, std::size_t bytes, bool old) {
      const fs::path p = dir.path / name;
      std::ofstream(p) << std::string(bytes, 'x');
      if (old) fs::last_write_time(p, fs::file_time_type::clock::now() - std::chrono::hours(1));
      return p;
    };
    const fs::path killed = plant(".hybrid-00000000deadbeef.bin.4242.0.tmp", 1 << 20, true);  // a SIGKILLed write
    const fs::path fresh = plant(".hybrid-00000000deadbeef.bin.4243.0.tmp", 1000, false);    // just created
    const fs::path live = plant(".hybrid-00000000cafef00d.bin.4244.0.tmp", 1 << 20, true);   // written, still locked
    const UniqueFd held(::open(live.c_str(), O_RDONLY | O_CLOEXEC));
    REQUIRE(::flock(held.get(), LOCK_EX | LOCK_NB) == 0);
    const fs::path other = plant("notes.tmp", 10, true);  // not the cache's: left alone
    CacheReport r;
    CacheOptions co{dir.path};
    co.max_bytes = 1.5 * (1 << 20);  // the live temporary file alone takes most of it
    precompute_cached(c.mesh, c.material, c.partition, {}, co, &r);
    CHECK(r.write_error == "");
    CHECK(r.stale_removed == 1);
    CHECK(!fs::exists(killed));
    CHECK(fs::exists(fresh));
    CHECK(fs::exists(live));
    CHECK(fs::exists(other));
    CHECK(fs::exists(r.file));  // the new entry is kept whatever the bound
    // Counted: with room for the temporary files and one and a half entries,
    // a second entry pushes the first out.
    co.max_bytes = double(fs::file_size(live) + fs::file_size(fresh)) + 1.5 * r.bytes;
    HybridCase d = c;  // another entry of the same size: one material differs
    d.material[0].young *= 2;
    CacheReport r2;
    precompute_cached(d.mesh, d.material, d.partition, {}, co, &r2);
    CHECK(r2.evicted == 1);
    CHECK(!fs::exists(r.file));
    CHECK(fs::exists(live));
  }

  TEST_CASE("no folder means no cache, and an unwritable folder is reported, not fatal") {
    std::mt19937 rng(34);
    const HybridCase c = test::random_case(rng, 0);
    CacheReport r;
    precompute_cached(c.mesh, c.material, c.partition, {}, {}, &r);
    CHECK(!r.enabled);
    TempDir dir;
    const fs::path blocked = dir.path / "file";
    std::ofstream(blocked) << "x";
    precompute_cached(c.mesh, c.material, c.partition, {}, {blocked / "sub"}, &r);
    CHECK(r.enabled);
    CHECK(!r.hit);
    CHECK(r.write_error != "");
  }
}
