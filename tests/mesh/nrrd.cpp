#include "mesh/volume/nrrd.hpp"

#include <doctest/doctest.h>
#include <sys/resource.h>

#include <string>

#include "core/error.hpp"
#include "test_support.hpp"
#include "volume_samples.hpp"

using namespace softcut;
using namespace softcut::mesh;
namespace fs = std::filesystem;

namespace {

const std::string kHead = "NRRD0004\n# a comment\ntype: ";

std::string header(const std::string& type, const std::string& encoding, const std::string& extra = "") {
  return kHead + type + "\ndimension: 3\nsizes: 3 2 2\nencoding: " + encoding + "\n" + extra;
}

std::string error_of(const fs::path& p) {
  Diagnostics d;
  try {
    read_nrrd_labels(p, d);
  } catch (const Error& e) {
    return e.what();
  }
  return "(no error)";
}

void check_sample(const LabelVolume& v) {
  CHECK(v.size == Eigen::Vector3i(3, 2, 2));
  const auto want = test::sample_labels();
  REQUIRE(v.labels.size() == want.size());
  for (size_t n = 0; n < want.size(); ++n) CHECK(v.labels[n] == want[n]);
}

}  // namespace

TEST_SUITE("mesh/volume/nrrd") {
  TEST_CASE("every integer type, both endians, raw and gzip, attached and detached") {
    const fs::path dir = test::scratch_dir("nrrd_types");
    const std::pair<const char*, int> types[] = {{"uint8", 1}, {"int8", 1},  {"uint16", 2},
                                                 {"short", 2}, {"uint32", 4}, {"int", 4}};
    int n = 0;
    for (const auto& type_bytes : types)
      for (bool big : {false, true})
        for (bool gz : {false, true})
          for (bool detached : {false, true}) {
            const char* type = type_bytes.first;  // not a structured binding: CAPTURE makes a lambda (clang 14)
            const int bytes = type_bytes.second;
            auto labels = test::sample_labels();
            if (std::string(type).find("int8") == 0 || type == std::string("short") || type == std::string("int"))
              labels[4] = -3;  // a negative label for the signed types
            std::string data = test::pack(labels, bytes, big);
            if (gz) data = test::gzip_bytes(data);
            const std::string hdr = header(type, gz ? "gzip" : "raw",
                                           std::string("endian: ") + (big ? "big" : "little") +
                                               "\nspacings: 0.5 0.5 2\nspace units: \"mm\" \"mm\" \"mm\"\n");
            const fs::path p = dir / ("v" + std::to_string(n++) + (detached ? ".nhdr" : ".nrrd"));
            if (detached) {
              test::write_bytes(dir / (p.stem().string() + ".raw"), data);
              test::write_bytes(p, hdr + "data file: " + p.stem().string() + ".raw\n");
            } else {
              test::write_bytes(p, hdr + "\n" + data);
            }
            Diagnostics d;
            const LabelVolume v = read_nrrd_labels(p, d);
            CAPTURE(type);
            CAPTURE(big);
            CAPTURE(gz);
            CAPTURE(detached);
            CHECK(d.warnings.empty());
            CHECK(v.size == Eigen::Vector3i(3, 2, 2));
            for (size_t k = 0; k < labels.size(); ++k) CHECK(v.labels[k] == labels[k]);
            CHECK(v.directions.diagonal().isApprox(Eigen::Vector3d(0.5e-3, 0.5e-3, 2e-3)));
          }
  }

  TEST_CASE("space directions, origin, units, ascii, skips and CRLF lines") {
    const fs::path dir = test::scratch_dir("nrrd_geometry");
    std::string ascii;
    for (long long x : test::sample_labels()) ascii += std::to_string(x) + " ";
    const fs::path p = dir / "a.nrrd";
    test::write_bytes(p, "NRRD0005\r\ntype: uchar\r\ndimension: 3\r\nsizes: 3 2 2\r\nencoding: ascii\r\n"
                         "space: left-posterior-superior\r\nspace directions: (0,0,1.5) (0, 2, 0) (1,0,0)\r\n"
                         "space origin: (10,20,30)\r\nspace units: \"cm\" \"cm\" \"cm\"\r\nkinds: domain domain "
                         "domain\r\nlabels:=ignored\r\n\r\n" + ascii);
    Diagnostics d;
    const LabelVolume v = read_nrrd_labels(p, d);
    check_sample(v);
    CHECK(v.directions.col(0).isApprox(Eigen::Vector3d(0, 0, 0.015)));
    CHECK(v.directions.col(1).isApprox(Eigen::Vector3d(0, 0.02, 0)));
    CHECK(v.origin.isApprox(Eigen::Vector3d(0.1, 0.2, 0.3)));
    CHECK(d.warnings.empty());

    // line skip + byte skip on a detached raw file; byte skip -1 takes the tail.
    const std::string raw = test::pack(test::sample_labels(), 2);
    test::write_bytes(dir / "d.raw", "junk line\nmore\nXYZ" + raw);
    test::write_bytes(dir / "d.nhdr", header("ushort", "raw", "endian: little\nline skip: 2\nbyte skip: 3\n"
                                                              "data file: d.raw\n"));
    Diagnostics d2;
    check_sample(read_nrrd_labels(dir / "d.nhdr", d2));
    REQUIRE(d2.warnings.size() == 2);  // no units: millimetres assumed; no spacings: unit cubes
    CHECK(d2.warnings[0].find("millimetres") != std::string::npos);
    CHECK(d2.warnings[1].find("unit cubes") != std::string::npos);
    test::write_bytes(dir / "e.nhdr", header("ushort", "raw", "endian: little\nbyte skip: -1\ndatafile: d.raw\n"));
    check_sample(read_nrrd_labels(dir / "e.nhdr", d2));
    NrrdReadOptions o;
    o.unit_m = 1;
    CHECK(read_nrrd_labels(dir / "e.nhdr", d2, o).directions == Eigen::Matrix3d::Identity());
  }

  TEST_CASE("malformed headers and data: file:line and what is wrong") {
    const fs::path dir = test::scratch_dir("nrrd_bad");
    const std::string ok_data = test::pack(test::sample_labels(), 1);
    struct Case {
      std::string text, message;
    };
    const Case cases[] = {
        {"NRRD0009\n", "x.nrrd:1: not a NRRD file"},
        {"P5 3 2\n", "x.nrrd:1: not a NRRD file"},
        {header("uchar", "raw", "garbage line\n"), "x.nrrd:7: expected 'field: value'"},
        {header("float", "raw"), "x.nrrd:3: type: 'float' is not a label type"},
        {header("quaternion", "raw"), "x.nrrd:3: type: unknown type 'quaternion'"},
        {kHead + "uchar\ndimension: 2\nsizes: 3 2\nencoding: raw\n\n", "x.nrrd:4: dimension: only 3D"},
        {kHead + "uchar\ndimension: 3\nsizes: 3 2\nencoding: raw\n\n", "x.nrrd:5: sizes: expected 3 sizes"},
        {kHead + "uchar\ndimension: 3\nsizes: 3 0 2\nencoding: raw\n\n", "x.nrrd:5: sizes: axis 1 size"},
        {kHead + "uchar\ndimension: 3\nsizes: 3 2 2\n\n", "lacks the required field 'encoding:'"},
        {header("uchar", "bzip2"), "x.nrrd:6: encoding: unsupported encoding 'bzip2'"},
        {header("uint16", "raw") + "\n", "lacks 'endian:'"},
        {header("uchar", "raw", "endian: middle\n"), "x.nrrd:7: endian: expected 'little' or 'big'"},
        {header("uchar", "raw", "spacings: 1 nan 1\n"), "x.nrrd:7: spacings: axis 1 spacing is NaN"},
        {header("uchar", "raw", "spacings: 1 1\n"), "x.nrrd:7: spacings: expected 3 spacings"},
        {header("uchar", "raw", "spacings: 1 1 1\nspace directions: (1,0,0) (0,1,0) (0,0,1)\n"),
         "x.nrrd:8: give either 'spacings' (line 7)"},
        {header("uchar", "raw", "space directions: (1,0,0) (0,1) (0,0,1)\n"),
         "x.nrrd:7: space directions: expected 3 components"},
        {header("uchar", "raw", "space directions: (1,0,0) none (0,0,1)\n"), "axis 1 is 'none'"},
        {header("uchar", "raw", "space directions: (1,0,0) (2,0,0) (0,0,1)\n"), "degenerate"},
        {header("uchar", "raw", "space origin: (1,x,0)\n"), "x.nrrd:7: space origin: expected a number, got 'x'"},
        {header("uchar", "raw", "space units: \"furlong\" \"mm\" \"mm\"\n"), "unknown length unit \"furlong\""},
        {header("uchar", "raw", "sizes: 1 1 1\n"), "x.nrrd:7: field 'sizes' given twice (first on line 5)"},
        {header("uchar", "raw"), "no data"},
        {header("uchar", "raw") + "\n" + ok_data.substr(0, 7), "data has 7 bytes, sizes 3 2 2 of type uchar need 12"},
        {header("uchar", "gzip") + "\n" + test::gzip_bytes(ok_data).substr(0, 12), "gzip data is corrupt or truncated"},
        {header("uchar", "raw", "data file: missing.raw\n"), "missing.raw: cannot open data file named on"},
        {header("uchar", "raw", "data file: LIST\n"), "x.nrrd:7: data file: only a single data file"},
        {header("uchar", "raw", "byte skip: -1\nencoding: gzip\n"), "given twice"},
        {header("uint32", "raw", "endian: little\n") + "\n" + test::pack({1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 0xffffffffLL}, 4),
         "label 4294967295 at voxel 11 does not fit"},
        {header("uchar", "ascii") + "\n1 2 3 4 x", "ascii value 4 ('x') is not a uchar"},
        {header("uchar", "ascii") + "\n1 2 3 4", "ascii data holds 4 values"},
        {header("uchar", "ascii") + "\n1 2 3 4 5 6 7 8 9 10 11 300", "ascii value 11 ('300') is not a uchar"},
    };
    for (const auto& c : cases) {
      test::write_bytes(dir / "x.nrrd", c.text);
      const std::string msg = error_of(dir / "x.nrrd");
      CAPTURE(c.text.substr(0, 200));
      CAPTURE(msg);
      CHECK(msg.find(c.message) != std::string::npos);
    }
    CHECK(error_of(dir / "nothing.nrrd").find("nothing.nrrd: cannot open NRRD file") != std::string::npos);
  }

  TEST_CASE("unknown fields and trailing data are warnings") {
    const fs::path dir = test::scratch_dir("nrrd_warn");
    test::write_bytes(dir / "w.nrrd", header("uchar", "raw", "frobnicate: yes\nspacings: 1 1 1\n") + "\n" +
                                          test::pack(test::sample_labels(), 1) + "extra");
    Diagnostics d;
    check_sample(read_nrrd_labels(dir / "w.nrrd", d));
    REQUIRE(d.warnings.size() == 3);
    CHECK(d.warnings[0].find("w.nrrd:7: unknown NRRD field 'frobnicate'") != std::string::npos);
    CHECK(d.warnings[1].find("millimetres") != std::string::npos);
    CHECK(d.warnings[2].find("5 bytes after the voxel data ignored") != std::string::npos);
  }

  TEST_CASE("a header announcing 2^28 voxels over a few bytes of data fails without allocating them") {
    // The labels (4 bytes a voxel: 1 and 2 GiB here) must not be allocated
    // before the data is known to hold them; peak memory may not grow by that
    // much. (The peak only rises, so the second case announces more voxels.)
    const fs::path dir = test::scratch_dir("nrrd_huge");
    const auto peak_kib = [] {
      rusage u{};
      getrusage(RUSAGE_SELF, &u);
      return long(u.ru_maxrss);
    };
    for (const char* enc : {"raw", "ascii"}) {
      const std::string sizes = enc == std::string("raw") ? "1024 1024 256" : "1024 1024 512";
      test::write_bytes(dir / "huge.nrrd",
                        kHead + "uchar\ndimension: 3\nsizes: " + sizes + "\nencoding: " + enc + "\n\n1 2 3 4 5\n");
      const long before = peak_kib();
      const std::string msg = error_of(dir / "huge.nrrd");
      CAPTURE(enc);
      CAPTURE(msg);
      CHECK(msg.find("huge.nrrd") != std::string::npos);
      CHECK(msg.find(enc == std::string("raw") ? "data has 10 bytes" : "ascii data holds 5 values") !=
            std::string::npos);
      CHECK(peak_kib() - before < 256 * 1024);
    }
  }
}
