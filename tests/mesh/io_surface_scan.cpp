// The structure scans bound what CGAL's readers would allocate from a file's
// own numbers: each case below announced far more than it held (or had a
// shape CGAL's reader misreads into a crash or an endless loop) and read with
// CGAL alone would have allocated gigabytes, crashed or hung.
#include "mesh/io/surface_scan.hpp"

#include <doctest/doctest.h>

#include <sys/resource.h>

#include <cstdint>

#include "mesh/io/surface_io.hpp"
#include "surface_samples.hpp"
#include "test_support.hpp"

using namespace softcut;
using namespace softcut::mesh;
using test::contains;
using test::error_of;

namespace {

long long peak_rss() {
  rusage u{};
  getrusage(RUSAGE_SELF, &u);
  return (long long)u.ru_maxrss * 1024;
}

std::string read_error(const std::string& ext, const std::string& bytes) {
  return error_of([&] {
    Diagnostics d;
    read_surface_bytes("in" + ext, ext, bytes, d);
  });
}

std::string le32(std::uint32_t v) { return std::string(reinterpret_cast<const char*>(&v), 4); }

const char* kPlyHead = "ply\nformat binary_little_endian 1.0\nelement vertex 3\nproperty float x\nproperty float y\n"
                       "property float z\nelement face 1\nproperty list int int vertex_indices\nend_header\n";

}  // namespace

TEST_SUITE("mesh/io/surface_scan") {
  TEST_CASE("counts announced past the data are refused before reading, in bounded memory") {
    const long long before = peak_rss();
    // OFF: CGAL resizes its arrays to the header's counts (2e9 vertices: 48 GB).
    CHECK(contains(read_error(".off", "OFF\n2000000000 2000000000 0\n0 0 0\n"), "announces 2000000000 vertices but the file ends after 1"));
    // PLY: a face's list resized to the count read (2^31 - 1 ints: 8 GB) ...
    const std::string pts(36, '\0');
    CHECK(contains(read_error(".ply", kPlyHead + pts + le32(0x7fffffff)), "needs 8589934588 more bytes"));
    // ... also past the end, from an uninitialised buffer: a truncated list count.
    CHECK(contains(read_error(".ply", kPlyHead + pts + "\x03\x00"), "needs 4 more bytes"));
    CHECK(contains(read_error(".ply", kPlyHead + pts + le32(0xffffffff)), "a negative list count -1"));
    // ASCII PLY: an int count past the tokens that follow.
    CHECK(contains(read_error(".ply", "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\n"
                                      "property float z\nelement face 1\nproperty list int int vertex_indices\nend_header\n"
                                      "0 0 0 1 0 0 0 1 0\n2000000000 0 1 2\n"),
                   "the data ends in item 0"));
    // Elements announced past the data.
    CHECK(contains(read_error(".ply", "ply\nformat binary_little_endian 1.0\nelement vertex 4000000000\nproperty float x\n"
                                      "property float y\nproperty float z\nelement face 1\nproperty list uchar int vertex_indices\n"
                                      "end_header\n"),
                   "announces 4000000000 items of 12 bytes"));
    // Binary STL: a triangle count past the file.
    CHECK(contains(read_error(".stl", std::string(80, 'x') + le32(100000000) + std::string(50, '\0')),
                   "binary STL announces 100000000 triangles (5000000084 bytes) but the file has 134 bytes"));
    CHECK(peak_rss() - before < (64 << 20));
  }

  TEST_CASE("shapes CGAL's readers misread are refused, naming the line") {
    // A property before any element: CGAL indexes an empty vector.
    CHECK(contains(read_error(".ply", "ply\nformat ascii 1.0\nproperty float x\nend_header\n"), "in.ply:3: a property before any element"));
    // An integer x: CGAL dereferences a null pointer.
    CHECK(contains(read_error(".ply", "ply\nformat ascii 1.0\nelement vertex 1\nproperty int x\nproperty float y\nproperty float z\n"
                                      "element face 0\nproperty list uchar int vertex_indices\nend_header\n1 0 0\n"),
                   "needs a float or double property 'x'"));
    // Items without properties: CGAL loops over the count without reading (2^63 times).
    CHECK(contains(read_error(".ply", "ply\nformat ascii 1.0\nelement junk 9223372036854775807\nelement vertex 0\nproperty float x\n"
                                      "property float y\nproperty float z\nelement face 0\nproperty list uchar int vertex_indices\n"
                                      "end_header\n"),
                   "element 'junk' has 9223372036854775807 items but no properties"));
    CHECK(contains(read_error(".ply", "ply\nformat ascii 1.0\nelement vertex 1\nproperty quad x\nend_header\n"), "unknown PLY type"));
    CHECK(contains(read_error(".ply", "ply\nformat ascii 1.0\nelement vertex 0\nproperty float x\nproperty float y\n"
                                      "property float z\nend_header\n"), "no face element"));
    CHECK(contains(read_error(".ply", "ply\nformat ascii 1.0\nelement vertex 1\n"), "no end_header"));
    CHECK(contains(read_error(".ply", "ply\nformat ascii 1.0\nelement halfedge 1\nproperty uint source\nend_header\n1\n"), "halfedge"));
    // OFF faces: a negative or fractional count, an index past the vertices (CGAL casts them to size_t).
    const std::string tri = "OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n";
    CHECK(contains(read_error(".off", tri + "-3 0 1 2\n"), "in.off:6: face 0 must be 'n i1 .. in'"));
    CHECK(contains(read_error(".off", tri + "3.5 0 1 2\n"), "face 0 must be"));
    CHECK(contains(read_error(".off", tri + "3 0 1 -2\n"), "face 0 uses vertex -2"));
    CHECK(contains(read_error(".off", tri + "3 0 1 3\n"), "face 0 uses vertex 3, not one of the 3 vertices"));
    // An edge count CGAL doubles in an int (signed overflow, found by a mutation run under UBSan).
    CHECK(contains(read_error(".off", "OFF\n3 1 2000000000\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n"), "expected the edge count"));
    // "OFF#...": CGAL eats the '#' with the keyword and reads the counts after it (a mutation run's find).
    CHECK(contains(read_error(".off", "OFF#2000000000 2000000000 0\n0 0 0\n"), "announces 2000000000 vertices"));
    CHECK(contains(read_error(".off", "OFF BINARY\n"), "binary OFF is not read"));
    CHECK(contains(read_error(".off", "COFF\n3 1 0\n"), "plain ASCII OFF"));
    CHECK(contains(read_error(".off", "OFF\n3 1 0\n0 0\n"), "vertex 0 needs three coordinates"));
    CHECK(contains(read_error(".stl", "abc"), "not an STL file"));
  }

  TEST_CASE("what the scans pass, CGAL reads") {
    const test::Soup c = test::cube(2);
    for (const auto& input : std::vector<std::pair<std::string, std::string>>{
             {".off", "# comment\nOFF # trailing\n\n8 12 0\n" + test::off_text(c).substr(11)},
             {".ply", test::ply_ascii(c)}, {".ply", test::ply_binary(c)}, {".stl", test::stl_binary(c)}}) {
      const std::string& ext = input.first;  // not a structured binding: clang 14's CAPTURE cannot take one
      const std::string& bytes = input.second;
      CAPTURE(ext);
      Diagnostics d;
      CHECK(read_surface_bytes("in" + ext, ext, bytes, d).triangles.rows() == 12);
    }
  }
}
