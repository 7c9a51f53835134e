#include "fem/reassembly.hpp"

#include <doctest/doctest.h>

#include <algorithm>
#include <cstring>
#include <functional>
#include <random>

#include "core/error.hpp"
#include "fem_fixtures.hpp"

using namespace softcut;

namespace {

// The same node rows, columns and blocks, bit for bit.
bool same_bits(const fem::BlockStiffness& a, const fem::BlockStiffness& b) {
  return a.row_start == b.row_start && a.col == b.col && a.blocks.size() == b.blocks.size() &&
         (a.blocks.empty() ||
          std::memcmp(a.blocks.data(), b.blocks.data(), a.blocks.size() * sizeof(a.blocks[0])) == 0);
}

// A body being cut: a mesh, its materials, the assembled tets and the node
// positions (free nodes of those tets in id order, as the operational
// system numbers them; fixed nodes have none).
struct Body {
  mesh::TetMesh m;
  std::vector<fem::Material> mats;
  std::vector<int> tets;
  std::vector<char> fixed;
  std::vector<int> position;
  int positions = 0;

  void number() {
    std::vector<char> used(size_t(m.num_nodes()), 0);
    for (int t : tets)
      for (int c = 0; c < 4; ++c) used[size_t(m.tets(t, c))] = 1;
    fixed.resize(size_t(m.num_nodes()), 0);
    position.assign(size_t(m.num_nodes()), -1);
    positions = 0;
    for (int v = 0; v < m.num_nodes(); ++v)
      if (used[size_t(v)] && !fixed[size_t(v)]) position[size_t(v)] = positions++;
  }
  fem::BlockStiffness assemble() const { return fem::assemble_node_blocks(m, mats, tets, position, positions); }
  fem::AssemblyInputs inputs() const { return fem::assembly_inputs(m, mats, tets, position, positions); }
  fem::BlockStiffness reassemble(const fem::BlockStiffness& K, const fem::AssemblyInputs& in,
                                 fem::ReassemblyReport* rep = nullptr, fem::AssemblyInputs* next = nullptr) const {
    return fem::reassemble_node_blocks(K, in, m, mats, tets, position, positions, rep, next);
  }

  // Splits tet t at its centroid (test::split_at_centroid): its children
  // carry its material and join the assembled tets.
  void split(int t) {
    const int nt = m.num_tets();
    test::split_at_centroid(m, t);
    mats.resize(size_t(nt + 3), mats[size_t(t)]);
    for (int k = 0; k < 3; ++k) tets.push_back(nt + k);
  }
};

Body random_body(unsigned seed) {
  Body b;
  b.m = test::jittered_box(3 + seed % 2, 3, 2 + seed % 3, 0.2, seed);
  b.mats = test::random_materials(b.m.num_tets(), seed);
  b.tets = test::random_subset(b.m.num_tets(), 0.7, seed);
  b.fixed.assign(size_t(b.m.num_nodes()), 0);
  for (int v = 0; v < b.m.num_nodes(); ++v) b.fixed[size_t(v)] = b.m.nodes(v, 2) < 1e-9;  // the bottom face
  b.number();
  return b;
}

}  // namespace

TEST_SUITE("fem/reassembly") {
  TEST_CASE("reassembly after changes of every kind equals a whole assembly bit for bit, step after step") {
    // Each step changes the body one way and reassembles from the last
    // step's matrix and inputs; every result must equal assemble_node_blocks.
    for (unsigned seed = 1; seed <= 12; ++seed) {
      CAPTURE(seed);
      Body b = random_body(seed);
      std::mt19937 rng(seed);
      auto pick = [&](int n) { return std::uniform_int_distribution<int>(0, n - 1)(rng); };
      fem::BlockStiffness K = b.assemble();
      fem::AssemblyInputs in = b.inputs();
      const std::vector<std::pair<const char*, std::function<void()>>> changes = {
          {"nothing", [] {}},
          {"a tet split at its centroid (id kept, tets and a node appended)",
           [&] { b.split(b.tets[size_t(pick(int(b.tets.size())))]); }},
          {"two tets split", [&] {
             b.split(b.tets[size_t(pick(int(b.tets.size())))]);
             b.split(b.tets[size_t(pick(int(b.tets.size())))]);
           }},
          {"a material changed", [&] { b.mats[size_t(b.tets[size_t(pick(int(b.tets.size())))])].young *= 1.5; }},
          {"an initial strain changed (not in K, but the material's bytes differ: its rows are reassembled)",
           [&] { b.mats[size_t(b.tets[0])].initial_strain[0] = -0.01; }},
          {"a node moved", [&] { b.m.nodes(b.m.tets(b.tets[size_t(pick(int(b.tets.size())))], 0), 0) += 1e-3; }},
          {"a tet left the set", [&] { b.tets.erase(b.tets.begin() + pick(int(b.tets.size()))); }},
          {"a tet joined the set", [&] {
             std::vector<int> out;
             for (int t = 0; t < b.m.num_tets(); ++t)
               if (!std::binary_search(b.tets.begin(), b.tets.end(), t)) out.push_back(t);
             if (out.empty()) return;
             const int t = out[size_t(pick(int(out.size())))];
             b.tets.insert(std::upper_bound(b.tets.begin(), b.tets.end(), t), t);
           }},
          {"a free node fixed (it leaves the positions)", [&] {
             for (int v = 0; v < b.m.num_nodes(); ++v)
               if (b.position[size_t(v)] >= 0 && pick(3) == 0) {
                 b.fixed[size_t(v)] = 1;
                 break;
               }
           }},
          {"a fixed node freed (it joins the positions)", [&] {
             for (int v = 0; v < b.m.num_nodes(); ++v)
               if (b.fixed[size_t(v)]) {
                 b.fixed[size_t(v)] = 0;
                 break;
               }
           }},
      };
      for (int step = 0; step < 3; ++step)
        for (const auto& [what, change] : changes) {
          const std::string name = what;
          CAPTURE(name);
          CAPTURE(step);
          change();
          b.number();
          fem::ReassemblyReport rep;
          fem::AssemblyInputs next;
          const fem::BlockStiffness R = b.reassemble(K, in, &rep, &next);
          const fem::BlockStiffness whole = b.assemble();
          REQUIRE(same_bits(R, whole));
          CHECK(rep.reused);
          CHECK(rep.rows == b.positions);
          if (name == "nothing") CHECK(rep.rows_assembled == 0);
          else CHECK(rep.rows_assembled < b.positions);  // a small change reassembles a few rows
          // The inputs handed on are the ones a fresh assembly records.
          const fem::AssemblyInputs fresh = b.inputs();
          CHECK(next.tets == fresh.tets);
          CHECK(next.corners == fresh.corners);
          CHECK(next.coords == fresh.coords);
          CHECK(next.node == fresh.node);
          CHECK(std::memcmp(next.material.data(), fresh.material.data(),
                            fresh.material.size() * sizeof(fem::Material)) == 0);
          K = R;
          in = std::move(next);
        }
    }
  }

  TEST_CASE("rows are reused only where nothing they sum changed: a moved node reassembles its neighbours' rows") {
    Body b = random_body(3);
    const fem::BlockStiffness K = b.assemble();
    const fem::AssemblyInputs in = b.inputs();
    int v = 0;  // a free node with neighbours
    while (b.position[size_t(v)] < 0) ++v;
    b.m.nodes(v, 1) += 1e-3;
    fem::ReassemblyReport rep;
    const fem::BlockStiffness R = b.reassemble(K, in, &rep);
    CHECK(same_bits(R, b.assemble()));
    // Exactly the rows of the positioned corners of v's tets.
    std::vector<char> expect(size_t(b.positions), 0);
    for (int t : b.tets)
      for (int c = 0; c < 4; ++c)
        if (b.m.tets(t, c) == v)
          for (int a = 0; a < 4; ++a)
            if (b.position[size_t(b.m.tets(t, a))] >= 0) expect[size_t(b.position[size_t(b.m.tets(t, a))])] = 1;
    CHECK(rep.rows_assembled == int(std::count(expect.begin(), expect.end(), 1)));
    CHECK(rep.rows_assembled > 1);
  }

  TEST_CASE("nothing to reuse: tets not in increasing order are assembled whole, with the same result") {
    Body b = random_body(5);
    const fem::BlockStiffness K = b.assemble();
    const fem::AssemblyInputs in = b.inputs();
    Body shuffled = b;
    std::reverse(shuffled.tets.begin(), shuffled.tets.end());
    fem::ReassemblyReport rep;
    const fem::BlockStiffness R = shuffled.reassemble(K, in, &rep);
    CHECK_FALSE(rep.reused);
    CHECK(rep.rows_assembled == b.positions);
    CHECK(same_bits(R, shuffled.assemble()));
    // Inputs of a shuffled assembly hold no tets: the next reassembly assembles every row.
    const fem::AssemblyInputs none = shuffled.inputs();
    CHECK(none.tets.empty());
    const fem::BlockStiffness R2 = b.reassemble(R, none, &rep);
    CHECK(rep.reused);
    CHECK(rep.rows_assembled == b.positions);
    CHECK(same_bits(R2, b.assemble()));
  }

  TEST_CASE("a changed tet that is inverted, or bad positions, are refused as the whole assembly refuses them") {
    Body b = random_body(7);
    const fem::BlockStiffness K = b.assemble();
    const fem::AssemblyInputs in = b.inputs();
    Body inverted = b;
    const int t = inverted.tets[2];
    const int a = inverted.m.tets(t, 0);
    inverted.m.tets(t, 0) = inverted.m.tets(t, 1);
    inverted.m.tets(t, 1) = a;
    const std::string named = "assemble_node_blocks: tetrahedron " + std::to_string(t);
    CHECK_THROWS_WITH_AS(inverted.reassemble(K, in), doctest::Contains(named.c_str()), Error);
    Body soft = b;
    soft.mats[size_t(soft.tets[1])].poisson = 0.5;
    CHECK_THROWS_WITH_AS(soft.reassemble(K, in), doctest::Contains("material of tetrahedron"), Error);
    CHECK_THROWS_WITH_AS(fem::reassemble_node_blocks(K, in, b.m, b.mats, b.tets, std::vector<int>(3, 0), b.positions),
                         doctest::Contains("3 node positions for a mesh of"), Error);
    CHECK_THROWS_WITH_AS(fem::reassemble_node_blocks(K, in, b.m, b.mats, {b.m.num_tets()}, b.position, b.positions),
                         doctest::Contains("out of range"), Error);
    CHECK_THROWS_WITH_AS(fem::reassemble_node_blocks(K, in, b.m, {}, b.tets, b.position, b.positions),
                         doctest::Contains("materials for"), Error);
  }
}
