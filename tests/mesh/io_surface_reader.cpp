#include <doctest/doctest.h>

#include <fstream>

#include "mesh/io/surface_io.hpp"
#include "surface_samples.hpp"
#include "test_support.hpp"

using namespace softcut;
using namespace softcut::mesh;
using test::contains;
using test::error_of;

namespace {

SurfaceSoup read(const std::string& ext, const std::string& bytes, Diagnostics* d = nullptr) {
  Diagnostics none;
  return read_surface_bytes("in" + ext, ext, bytes, d ? *d : none);
}

// The triangles of a soup as sets of three points, for comparing readers.
double enclosed_volume(const SurfaceSoup& s) {
  double v = 0;
  for (Eigen::Index t = 0; t < s.triangles.rows(); ++t) {
    const Eigen::Vector3d a = s.points.row(s.triangles(t, 0)), b = s.points.row(s.triangles(t, 1)),
                          c = s.points.row(s.triangles(t, 2));
    v += a.dot(b.cross(c)) / 6;
  }
  return v;
}

}  // namespace

TEST_SUITE("mesh/io/surface_reader") {
  TEST_CASE("every format reads the same closed surface") {
    const test::Soup c = test::cube(0.02);
    for (const auto& input : std::vector<std::pair<std::string, std::string>>{
             {".off", test::off_text(c)}, {".obj", test::obj_text(c)}, {".stl", test::stl_ascii(c)},
             {".stl", test::stl_binary(c)}, {".ply", test::ply_ascii(c)}, {".ply", test::ply_binary(c)}}) {
      const std::string& ext = input.first;  // not a structured binding: clang 14's CAPTURE cannot take one
      const std::string& bytes = input.second;
      CAPTURE(ext);
      const SurfaceSoup s = read(ext, bytes);
      CHECK(s.triangles.rows() == 12);
      CHECK(s.points.rows() == 8);  // STL's repeated corners merged by CGAL's reader
      CHECK(enclosed_volume(s) == doctest::Approx(8e-6).epsilon(1e-6));
    }
  }

  TEST_CASE("the samples written by meshio read, through the checked open") {
    Diagnostics d;
    const auto dir = test::data_dir() / "surface";
    CHECK(read_surface(dir / "sphere_mm.stl", d).triangles.rows() == 1280);
    CHECK(read_surface(dir / "torus_m.ply", d).triangles.rows() == 2304);
    CHECK(read_surface(dir / "outer_mm.off", d).triangles.rows() == 1280);
    CHECK(read_surface(dir / "inner_mm.obj", d).triangles.rows() == 320);
    CHECK(d.warnings.empty());
    ReadOptions below;
    below.root = dir;
    CHECK(read_surface(dir / "torus_m.ply", d, below).points.rows() == 48 * 24);
    ReadOptions small;
    small.max_bytes = 4 * 1000;  // the file may take a quarter
    CHECK(contains(error_of([&] { read_surface(dir / "sphere_mm.stl", d, small); }), "sphere_mm.stl"));
  }

  TEST_CASE("polygons are split into triangles, with a warning - unused points are named") {
    Diagnostics d;
    const std::string quads = "OFF\n9 1 0\n0 0 0\n1 0 0\n1 1 0\n0 1 0\n5 5 5\n6 6 6\n7 7 7\n8 8 8\n9 9 9\n4 0 1 2 3\n";
    const SurfaceSoup s = read(".off", quads, &d);
    CHECK(s.triangles.rows() == 2);
    REQUIRE(d.warnings.size() == 2);
    CHECK(contains(d.warnings[0], "1 faces with more than 3 vertices were split"));
    CHECK(contains(d.warnings[1], "5 points are used by no face"));
  }

  TEST_CASE("bad files: one-line reasons naming the file") {
    CHECK(contains(error_of([] { read(".stl", ""); }), "in.stl: the file holds no faces"));
    CHECK(contains(error_of([] { read(".obj", "\n  \n"); }), "in.obj: the file is empty"));
    CHECK(contains(error_of([] { read(".off", "OFF\n0 0 0\n"); }), "no faces"));
    CHECK(contains(error_of([] { read(".vrml", "x"); }), "unknown surface file extension '.vrml'"));
    // CGAL's OBJ reader lets index n+1 through (its check is off by one): softcut's is not.
    CHECK(contains(error_of([] { read(".obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 4\n"); }), "face 0 uses point 3 but the file has 3 points"));
    CHECK(contains(error_of([] { read(".obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 0\n"); }), "face 0 uses point"));
    CHECK(contains(error_of([] { read(".off", "OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n2 0 1\n"); }), "face 0 has 2 vertices"));
    CHECK(contains(error_of([] { read(".obj", "v 0 0 nan\nv 1 0 0\nv 0 1 0\nf 1 2 3\n"); }), "in.obj"));
    CHECK(contains(error_of([] { read(".ply", "ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\nproperty float y\n"
                                              "property float z\nelement face 0\nproperty list uchar int vertex_indices\n"
                                              "end_header\n0 0 0\n"); }),
                   "no faces"));
    // A message quoting the file's bytes is printable.
    const std::string e = error_of([] { read(".off", "\x1b[31mOFF\n"); });
    CHECK(e.find('\x1b') == std::string::npos);
  }
}
