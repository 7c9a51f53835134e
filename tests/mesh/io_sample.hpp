#pragma once
// The sample mesh every hand-written file in tests/data/mesh holds: 6 nodes
// (node 2 referenced by no tet), two tets labelled 7 and 9, the second stored
// negatively oriented, and (where the format has them) a line and a triangle.
#include <doctest/doctest.h>

#include <filesystem>
#include <fstream>
#include <functional>
#include <sstream>
#include <string>

#include "core/error.hpp"
#include "mesh/io/mesh_io.hpp"
#include "test_support.hpp"

namespace softcut::test {

inline std::filesystem::path mesh_data(const std::string& name) { return data_dir() / "mesh" / name; }

inline bool has_warning(const Diagnostics& d, const std::string& part) {
  for (const auto& w : d.warnings)
    if (w.find(part) != std::string::npos) return true;
  return false;
}

// Reads `path` and checks it is the sample mesh; `skipped` is the number of
// non-tet elements the file holds (0 where the format cannot hold any).
inline void check_sample(const std::filesystem::path& path, int skipped) {
  INFO("file: ", path.string());
  Diagnostics diag;
  const mesh::TetMesh m = mesh::read_mesh(path, diag);
  REQUIRE(m.num_nodes() == 6);
  REQUIRE(m.num_tets() == 2);
  const double xyz[6][3] = {{0, 0, 0}, {1, 0, 0}, {5, 5, 5}, {0, 1, 0}, {0, 0, 1}, {1, 1, 1}};
  for (int i = 0; i < 6; ++i)
    for (int c = 0; c < 3; ++c) CHECK(m.nodes(i, c) == xyz[i][c]);
  // File order (0 1 3 4) and (1 4 3 5); the second is flipped by validate.
  const int tets[2][4] = {{0, 1, 3, 4}, {1, 4, 5, 3}};
  for (int t = 0; t < 2; ++t)
    for (int k = 0; k < 4; ++k) CHECK(m.tets(t, k) == tets[t][k]);
  CHECK(m.labels(0) == 7);
  CHECK(m.labels(1) == 9);
  CHECK(has_warning(diag, "reoriented 1 "));
  CHECK(has_warning(diag, "1 node(s) are used by no tetrahedron (first: 2)"));
  if (skipped > 0) CHECK(has_warning(diag, cat("skipped ", skipped, " element(s)")));
  else CHECK(!has_warning(diag, "skipped"));
}

inline void spit(const std::filesystem::path& p, const std::string& s) {
  std::ofstream out(p, std::ios::binary);
  out << s;
}

// Writes `text` to scratch file `name` and expects read_mesh to throw an
// Error whose message contains each of `parts`.
inline void expect_error(const std::string& name, const std::string& text, std::initializer_list<std::string> parts) {
  const auto dir = scratch_dir("io_errors");
  const auto path = dir / name;
  spit(path, text);
  Diagnostics diag;
  std::string msg;
  try {
    mesh::read_mesh(path, diag);
  } catch (const Error& e) {
    msg = e.what();
  }
  INFO("message: ", msg);
  REQUIRE(!msg.empty());
  CHECK(msg.find(name) != std::string::npos);
  for (const auto& p : parts) CHECK(msg.find(p) != std::string::npos);
}

// Replaces the first occurrence of `from` in `s` (which must contain it).
inline std::string replaced(std::string s, const std::string& from, const std::string& to) {
  const auto at = s.find(from);
  REQUIRE(at != std::string::npos);
  return s.replace(at, from.size(), to);
}

}  // namespace softcut::test
