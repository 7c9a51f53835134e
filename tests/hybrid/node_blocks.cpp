#include "hybrid/node_blocks.hpp"

#include <doctest/doctest.h>

#include <random>

#include "fem/assembly.hpp"
#include "fixtures.hpp"

using namespace softcut;
using namespace softcut::hybrid;

TEST_SUITE("hybrid/node_blocks") {
  TEST_CASE("node_block picks the right entries for arbitrary node orders") {
    std::mt19937 rng(41);
    const mesh::TetMesh m = test::random_box(rng, 2);
    const SparseMatrix K = fem::assemble_stiffness(m, std::vector<fem::Material>(size_t(m.num_tets())));
    const Eigen::MatrixXd Kd(K);
    std::vector<int> rows = {5, 0, 3, m.num_nodes() - 1}, cols = {2, 7, 1};
    const SparseMatrix B = node_block(K, rows, cols);
    CHECK(B.rows() == 12);
    CHECK(B.cols() == 9);
    const Eigen::MatrixXd Bd(B);
    for (size_t a = 0; a < rows.size(); ++a)
      for (size_t b = 0; b < cols.size(); ++b)
        for (int r = 0; r < 3; ++r)
          for (int c = 0; c < 3; ++c)
            CHECK(Bd(3 * Eigen::Index(a) + r, 3 * Eigen::Index(b) + c) == Kd(3 * rows[a] + r, 3 * cols[b] + c));
    Eigen::MatrixX3d field = Eigen::MatrixX3d::Random(m.num_nodes(), 3);
    const Eigen::VectorXd x = gather_nodes(field, rows);
    Eigen::MatrixX3d back = Eigen::MatrixX3d::Zero(m.num_nodes(), 3);
    scatter_nodes(x, rows, back);
    for (int v : rows) CHECK(back.row(v) == field.row(v));
    CHECK(node_positions(rows, m.num_nodes())[3] == 2);
    CHECK(node_positions(rows, m.num_nodes())[4] == -1);
  }
}
