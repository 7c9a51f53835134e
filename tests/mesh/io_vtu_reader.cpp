#include <doctest/doctest.h>

#include <zlib.h>

#include "io_sample.hpp"
#include "mesh/io/base64.hpp"

#include <algorithm>
#include <cctype>
#include <cstring>

using softcut::mesh::io::base64_decode;
using softcut::mesh::io::base64_encode;
using softcut::test::check_sample;
using softcut::test::expect_error;
using softcut::test::mesh_data;
using softcut::test::replaced;
using softcut::test::slurp;

namespace {
// The base64 text of the first DataArray named `name` in `xml`.
std::string array_text(const std::string& xml, const std::string& name) {
  const auto tag = xml.find("Name=\"" + name + "\"");
  const auto begin = xml.find('>', tag) + 1;
  const auto end = xml.find("</DataArray>", begin);
  std::string s = xml.substr(begin, end - begin);
  s.erase(std::remove_if(s.begin(), s.end(), [](char c) { return std::isspace((unsigned char)c); }), s.end());
  return s;
}

void put_u32(std::string& bytes, std::size_t at, std::uint32_t v) { std::memcpy(bytes.data() + at, &v, 4); }
void put_u64(std::string& bytes, std::size_t at, std::uint64_t v) { std::memcpy(bytes.data() + at, &v, 8); }

std::string zlib(const std::string& raw) {
  uLongf n = compressBound(uLong(raw.size()));
  std::string out(n, '\0');
  REQUIRE(compress2(reinterpret_cast<Bytef*>(out.data()), &n, reinterpret_cast<const Bytef*>(raw.data()),
                    uLong(raw.size()), 6) == Z_OK);
  out.resize(n);
  return out;
}
}  // namespace

TEST_SUITE("mesh/io/vtu_reader") {
  TEST_CASE("ascii, base64, zlib, big-endian and appended variants read to the sample mesh") {
    for (const char* name : {"sample_ascii.vtu", "sample_base64_uint32.vtu", "sample_base64_uint64.vtu",
                             "sample_base64_bigendian.vtu", "sample_zlib_uint32.vtu", "sample_zlib_uint64.vtu",
                             "sample_appended_raw.vtu", "sample_appended_base64_zlib.vtu"})
      check_sample(mesh_data(name), 2);
  }

  TEST_CASE("malformed ascii files name the line and the problem") {
    const std::string a = slurp(mesh_data("sample_ascii.vtu"));
    expect_error("count.vtu", replaced(a, "0 1 0 1 3 0 1 3 4 1 4 3 5", "0 1 0 1 3 0 1 3 4 1 4 3"),
                 {"count.vtu:14:", "DataArray 'connectivity': expected 13 values, found 12"});
    expect_error("extra.vtu", replaced(a, "\n  2 5 9 13", "\n  2 5 9 13\n 17"), {"extra.vtu:19:", "more than the 4 values expected"});
    expect_error("range.vtu", replaced(a, "1 4 3 5", "1 4 3 6"), {"range.vtu:14:", "cell 3 refers to point 6, but the file has points 0..5"});
    expect_error("short.vtu", replaced(replaced(a, "1 4 3 5", "1 4 3"), "2 5 9 13", "2 5 9 12"),
                 {"short.vtu:17:", "cell 3 is a tetrahedron (type 10) with 3 points; expected 4"});
    expect_error("nan.vtu", replaced(a, "5 5 5", "5 nan 5"), {"nan.vtu:9:", "point 2 has a non-finite coordinate"});
    expect_error("badnum.vtu", replaced(a, "5 5 5", "5 5q 5"), {"badnum.vtu:10:", "found '5q'"});
    expect_error("offsets.vtu", replaced(a, "2 5 9 13", "2 9 5 13"), {"offsets.vtu:17:", "offset of cell 2 (5)"});
    expect_error("type.vtu", replaced(a, "UnstructuredGrid\" version", "PolyData\" version"), {"type.vtu:3:", "'PolyData' is not supported"});
    expect_error("lz4.vtu", replaced(a, "header_type=\"UInt32\"", "header_type=\"UInt32\" compressor=\"vtkLZ4DataCompressor\""),
                 {"lz4.vtu:3:", "compressor 'vtkLZ4DataCompressor' is not supported"});
    expect_error("pieces.vtu", replaced(a, "</Piece>", "</Piece><Piece NumberOfPoints=\"1\" NumberOfCells=\"0\"></Piece>"),
                 {"pieces.vtu:", "more than one <Piece>"});
    expect_error("unclosed_piece.vtu", replaced(a, "</Piece>", "</Piece><Piece NumberOfPoints=\"1\" NumberOfCells=\"0\">"),
                 {"unclosed_piece.vtu:33:", "does not match the innermost open element, <Piece> (line 32)"});
    expect_error("unclosed.vtu", a.substr(0, a.find("</DataArray>")), {"unclosed.vtu:9:", "DataArray 'Points' has no </DataArray>"});
    expect_error("tag.vtu", replaced(a, "<Piece NumberOfPoints=\"6\"", "<Piece NumberOfPoints=6"), {"tag.vtu:5:", "is not quoted"});
    expect_error("nopiece.vtu", a.substr(0, a.find("<Piece")), {"nopiece.vtu", "no <Piece> element"});
    expect_error("noconn.vtu", replaced(a, "Name=\"connectivity\"", "Name=\"conn\""), {"noconn.vtu", "no Cells 'connectivity' DataArray"});
    expect_error("celltype.vtu", replaced(a, "3 5 10 10", "3 5 10 10.5"), {"celltype.vtu:20:", "type 10.5 of cell 3 is not an integer"});
    expect_error("label.vtu", replaced(a, "1 2 7 9", "1 2 7 9.5"), {"label.vtu:28:", "label 9.5 of cell 3 is not an integer"});
  }

  TEST_CASE("XML as any XML reader takes it: comments inside arrays, CDATA, entities in names, a '>' in a value") {
    const std::string a = slurp(mesh_data("sample_ascii.vtu"));
    std::string x = replaced(a, "0 1 0 1 3 0 1 3 4 1 4 3 5", "0 1 0 1 3 <!-- half way --> 0 1 3 4 <![CDATA[1 4 3 5]]>");
    x = replaced(x, "<VTKFile ", "<!-- a comment with <Piece> and </DataArray> in it -->\n<VTKFile note=\"a > b\" ");
    const auto path = softcut::test::scratch_dir("io_errors") / "xml.vtu";
    softcut::test::spit(path, x);
    check_sample(path, 2);
    // Entities are decoded: a Name spelled with a character reference is found (the hand-written
    // scanner this reader replaced compared the raw text and missed it).
    const auto ent = softcut::test::scratch_dir("io_errors") / "entity.vtu";
    softcut::test::spit(ent, replaced(x, "Name=\"connectivity\"", "Name=\"conn&#101;ctivity\""));
    check_sample(ent, 2);
    // A million nested elements: refused by depth, not by a stack overflow.
    std::string deep;
    for (int i = 0; i < 1000000; ++i) deep += "<a>";
    for (int i = 0; i < 1000000; ++i) deep += "</a>";
    expect_error("deep.vtu", replaced(a, "<PointData>", "<PointData>" + deep),
                 {"deep.vtu:", "nested more than 64 deep"});
  }

  TEST_CASE("malformed binary data: bad base64, lying headers, corrupt zlib, truncated appended data") {
    const std::string b = slurp(mesh_data("sample_base64_uint32.vtu"));
    const std::string pts = array_text(b, "Points");
    expect_error("b64.vtu", replaced(b, pts.substr(0, 8), pts.substr(0, 4) + "!" + pts.substr(5, 3)), {"b64.vtu:10:", "invalid base64"});
    {
      std::string bytes = *base64_decode(pts);
      put_u32(bytes, 0, 4000000000u);  // announces 4 GB of points
      expect_error("lie.vtu", replaced(b, pts, base64_encode(bytes)), {"lie.vtu:9:", "header announces 4000000000 bytes but only 144 follow"});
      put_u32(bytes, 0, 136);
      expect_error("short.vtu", replaced(b, pts, base64_encode(bytes)), {"short.vtu:9:", "expected 18 values of type Float64 (144 bytes), found 136 bytes"});
    }
    const std::string z = slurp(mesh_data("sample_zlib_uint32.vtu"));
    const std::string zpts = array_text(z, "Points");
    // Header and data are separate base64 streams here: 3 + 9 UInt32 = 48 bytes -> 64 characters.
    std::string head = *base64_decode(zpts.substr(0, 64));
    const std::string data = zpts.substr(64);
    {
      std::string h = head;
      put_u32(h, 0, 1000000000u);
      expect_error("zblocks.vtu", replaced(z, zpts, base64_encode(h) + data), {"zblocks.vtu:9:", "announces 1000000000 blocks"});
      h = head;
      put_u32(h, 4, 2000000000u);  // block size far beyond what the compressed bytes can hold
      expect_error("zsize.vtu", replaced(z, zpts, base64_encode(h) + data), {"zsize.vtu:9:", "more than", "compressed bytes can hold"});
      std::string d = *base64_decode(data);
      d[5] = char(d[5] ^ 0x55);
      expect_error("zcorrupt.vtu", replaced(z, zpts, base64_encode(head) + base64_encode(d)), {"zcorrupt.vtu:9:", "zlib block 0 does not decompress"});
    }
    {
      // UInt64 header with two zlib blocks whose compressed sizes are each
      // 2^63 too large: their sum wraps around to the true total, so a reader
      // that checks only the sum steps 2^63 bytes past the data for block 1.
      const std::string a = slurp(mesh_data("sample_ascii.vtu"));
      std::string points(144, '\0');
      const double xyz[18] = {0, 0, 0, 1, 0, 0, 5, 5, 5, 0, 1, 0, 0, 0, 1, 1, 1, 1};
      std::memcpy(points.data(), xyz, 144);
      const std::string c0 = zlib(points.substr(0, 72)), c1 = zlib(points.substr(72));
      std::string h(5 * 8, '\0');
      put_u64(h, 0, 2), put_u64(h, 8, 72), put_u64(h, 16, 72);
      put_u64(h, 24, c0.size() + (std::uint64_t(1) << 63)), put_u64(h, 32, c1.size() + (std::uint64_t(1) << 63));
      const auto with_points = [&](const std::string& header) {
        const std::string z =
            replaced(a, "header_type=\"UInt32\"", "header_type=\"UInt64\" compressor=\"vtkZLibDataCompressor\"");
        return replaced(z, "NumberOfComponents=\"3\" format=\"ascii\">\n  0 0 0 1 0 0 5 5 5 0 1 0 0 0 1 1 1 1",
                        "NumberOfComponents=\"3\" format=\"binary\">\n  " + base64_encode(header + c0 + c1));
      };
      expect_error("zwrap.vtu", with_points(h), {"zwrap.vtu:9:", "DataArray 'Points'", "compressed"});
      // The same blocks with honest sizes read to the sample mesh.
      put_u64(h, 24, c0.size()), put_u64(h, 32, c1.size());
      const auto path = softcut::test::scratch_dir("io_errors") / "zhonest.vtu";
      softcut::test::spit(path, with_points(h));
      check_sample(path, 2);
    }
    const std::string raw = slurp(mesh_data("sample_appended_raw.vtu"));
    {
      // A comment naming <AppendedData> before the real one is a comment.
      const auto path = softcut::test::scratch_dir("io_errors") / "comment_appended.vtu";
      softcut::test::spit(path, replaced(raw, "<VTKFile ", "<!-- <AppendedData encoding=\"raw\"> _ -->\n<VTKFile "));
      check_sample(path, 2);
    }
    expect_error("rawtrunc.vtu", raw.substr(0, raw.find("_", raw.find("<AppendedData")) + 100), {"rawtrunc.vtu:", "DataArray 'Points': header announces 144 bytes but only"});
    expect_error("noappended.vtu", raw.substr(0, raw.find("<AppendedData")), {"noappended.vtu:", "format=\"appended\" but the file has no <AppendedData>"});
    expect_error("offset.vtu", replaced(raw, "offset=\"0\"", "offset=\"99999\""), {"offset.vtu:", "offset 99999 lies beyond the appended data"});
  }
}
