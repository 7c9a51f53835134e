// softcut mesh outside a scenario keeps bounds too (issue #38, item 10):
// files that decode to gigabytes are refused before they are inflated, every
// count a command line can ask for is refused before meshing, and every
// command ends at its --timeout. Before, `mesh info` on a 1.4 MB zlib VTU
// peaked past 1.4 GB, `mesh generate volume` on a 1 MB gzip NRRD past 5 GB,
// and `liver --target-tets 1000000000` meshed without end.
#include <doctest/doctest.h>
#include <zlib.h>

#include <chrono>
#include <cstdint>
#include <string>

#include "app/commands.hpp"
#include "hardening_support.hpp"

namespace fs = std::filesystem;
using softcut::hardening::contains;
using softcut::hardening::peak_rss_bytes;
using softcut::hardening::put_file;
using softcut::hardening::run_softcut;

namespace {

std::string mesh_error(const softcut::app::Args& args) {
  try {
    softcut::app::cmd_mesh(args);
  } catch (const softcut::Error& e) {
    return e.what();
  }
  return "(no error)";
}

std::string u64(std::uint64_t v) { return std::string(reinterpret_cast<const char*>(&v), 8); }

// A VTU whose points (Float64 x 3) are `blocks` zlib blocks of ~1 MiB of
// zeros, appended raw: ~1 KB per block on disk, ~1 MiB each decoded.
std::string zlib_vtu(std::uint64_t blocks) {
  const std::uint64_t bs = 24 * 43690;  // whole points per block
  const std::string zeros(bs, '\0');
  std::string z(compressBound(uLong(bs)), '\0');
  uLongf zn = uLongf(z.size());
  compress2(reinterpret_cast<Bytef*>(z.data()), &zn, reinterpret_cast<const Bytef*>(zeros.data()), uLong(bs), 9);
  z.resize(zn);
  const std::uint64_t points = blocks * (bs / 24);
  std::string head = u64(blocks) + u64(bs) + u64(0);
  for (std::uint64_t b = 0; b < blocks; ++b) head += u64(z.size());
  std::string data = head;
  for (std::uint64_t b = 0; b < blocks; ++b) data += z;
  return "<?xml version=\"1.0\"?>\n<VTKFile type=\"UnstructuredGrid\" version=\"1.0\" byte_order=\"LittleEndian\" "
         "header_type=\"UInt64\" compressor=\"vtkZLibDataCompressor\">\n<UnstructuredGrid><Piece NumberOfPoints=\"" +
         std::to_string(points) + "\" NumberOfCells=\"1\">\n<Points><DataArray type=\"Float64\" NumberOfComponents=\"3\" "
         "format=\"appended\" offset=\"0\"/></Points>\n<Cells><DataArray type=\"Int64\" Name=\"connectivity\" "
         "format=\"ascii\">0 1 2 3</DataArray><DataArray type=\"Int64\" Name=\"offsets\" format=\"ascii\">4</DataArray>"
         "<DataArray type=\"UInt8\" Name=\"types\" format=\"ascii\">10</DataArray></Cells>\n</Piece></UnstructuredGrid>\n"
         "<AppendedData encoding=\"raw\">_" + data + "</AppendedData></VTKFile>\n";
}

// An attached-header NRRD of 1000^3 uchar voxels, gzip: one member of 1 MiB
// of zeros repeated (inflate reads concatenated members), ~1 MB on disk.
std::string gzip_nrrd() {
  const std::size_t bs = 1 << 20;
  const std::string zeros(bs, '\0');
  z_stream zs{};
  deflateInit2(&zs, 9, Z_DEFLATED, 15 + 16, 9, Z_DEFAULT_STRATEGY);
  std::string member(deflateBound(&zs, uLong(bs)), '\0');
  zs.next_in = reinterpret_cast<Bytef*>(const_cast<char*>(zeros.data()));
  zs.avail_in = uInt(bs);
  zs.next_out = reinterpret_cast<Bytef*>(member.data());
  zs.avail_out = uInt(member.size());
  deflate(&zs, Z_FINISH);
  member.resize(member.size() - zs.avail_out);
  deflateEnd(&zs);
  std::string out = "NRRD0004\ntype: uchar\ndimension: 3\nsizes: 1000 1000 1000\nencoding: gzip\nspacings: 1 1 1\n\n";
  for (int i = 0; i < 955; ++i) out += member;  // 955 MiB > 1e9 bytes
  return out;
}

}  // namespace

TEST_SUITE("hardening/mesh_limits") {
  TEST_CASE("mesh info on a zlib VTU that inflates to 1.4 GB: refused before inflating") {
    const fs::path dir = softcut::test::scratch_dir("mesh_limits_vtu");
    const fs::path bomb = put_file(dir / "bomb.vtu", zlib_vtu(1400));
    CHECK(fs::file_size(bomb) < 3'000'000);
    const long long before = peak_rss_bytes();
    const std::string e = mesh_error({"info", bomb.string()});
    CHECK(contains(e, "bomb.vtu"));
    CHECK(contains(e, "--max-memory"));
    CHECK(peak_rss_bytes() - before < (64 << 20));
  }

  TEST_CASE("mesh generate volume on a 1 MB gzip NRRD of 1000^3 voxels: refused before inflating") {
    const fs::path dir = softcut::test::scratch_dir("mesh_limits_nrrd");
    const fs::path bomb = put_file(dir / "bomb.nrrd", gzip_nrrd());
    CHECK(fs::file_size(bomb) < 2'000'000);
    const long long before = peak_rss_bytes();
    const std::string e = mesh_error({"generate", "volume", bomb.string(), (dir / "out.vtu").string()});
    CHECK(contains(e, "bomb.nrrd: sizes 1000 1000 1000 of type uchar (1000000000 voxels) need"));
    CHECK(contains(e, "--max-memory"));
    CHECK(peak_rss_bytes() - before < (64 << 20));
  }

  TEST_CASE("counts on the command line are refused before meshing, with the bound that refused them") {
    const fs::path out = softcut::test::scratch_dir("mesh_limits_counts") / "x.vtu";
    const auto t0 = std::chrono::steady_clock::now();
    const long long before = peak_rss_bytes();
    const std::string liver = mesh_error({"generate", "liver", "--target-tets", "1000000000", out.string()});
    CHECK(contains(liver, "over this run's limit of 2000000"));
    CHECK(contains(liver, "--max-tets N raises the limit"));
    CHECK(contains(mesh_error({"generate", "liver", "--cell-size", "1e-9", out.string()}), "over this run's limit"));
    // llround(inf) printed -9223372036854775808 tetrahedra.
    const std::string tiny = mesh_error({"generate", "liver", "--cell-size", "1e-300", out.string()});
    CHECK(contains(tiny, "about infinitely many tetrahedra"));
    CHECK(!contains(tiny, "-9223372036854775808"));
    // A tube's resolution search ends at 2.5M tets: a target it cannot reach is an error, not a silent miss
    // (past the tet limit first; with a higher limit, the target).
    CHECK(contains(mesh_error({"generate", "tube", "--target-tets", "1000000000", out.string()}),
                   "this resolution gives 2484300 tetrahedra, over this run's limit of 2000000"));
    const std::string tube = mesh_error({"generate", "tube", "--target-tets", "1000000000", "--max-tets", "3000000", out.string()});
    CHECK(contains(tube, "tube: cannot meet target_tets 1000000000 within 25 %"));
    CHECK(contains(tube, "give the cell counts (radial, around, layers)"));
    CHECK(contains(mesh_error({"generate", "box", "--cells", "1000,1000,300", out.string()}), "1800000000 tetrahedra"));
    CHECK(contains(mesh_error({"generate", "volume", (softcut::test::data_dir() / "volume" / "organ.nhdr").string(), "--smooth",
                               "1000000000", out.string()}),
                   "--smooth 1000000000 not in range 0 to"));
    CHECK(contains(mesh_error({"generate", "volume", (softcut::test::data_dir() / "volume" / "organ.nhdr").string(),
                               "--max-tets", "100", out.string()}),
                   "over the limit of 100"));
    CHECK(std::chrono::steady_clock::now() - t0 < std::chrono::seconds(30));
    CHECK(peak_rss_bytes() - before < (64 << 20));
  }

  TEST_CASE("every mesh command ends at its --timeout with exit status 124") {
    const fs::path dir = softcut::test::scratch_dir("mesh_limits_time");
    // Meshing polls the deadline (softcut's seeding, then CGAL's refinement): it stops and says so.
    auto t0 = std::chrono::steady_clock::now();
    auto r = run_softcut("mesh generate liver --target-tets 1500000 --timeout 1 out.vtu", dir);
    CHECK(r.status == 124);
    CHECK(contains(r.output, "meshing stopped at the time limit"));
    CHECK(std::chrono::steady_clock::now() - t0 < std::chrono::seconds(20));
    CHECK(!fs::exists(dir / "out.vtu"));
    // Voxel smoothing polls nothing: the watchdog ends the process after its grace.
    // (48^3 voxels, 660k tets: the smoothing takes ~15 s without a limit.)
    std::string nrrd = "NRRD0004\ntype: uchar\ndimension: 3\nsizes: 48 48 48\nencoding: raw\nspacings: 1 1 1\n\n";
    nrrd += std::string(48 * 48 * 48, '\1');
    put_file(dir / "cube.nrrd", nrrd);
    t0 = std::chrono::steady_clock::now();
    r = run_softcut("mesh generate volume cube.nrrd --smooth 1000 --timeout 1 out.vtu", dir);
    CHECK(r.status == 124);
    CHECK(contains(r.output, "the wall-clock limit of 1 s (--timeout) was reached"));
    CHECK(std::chrono::steady_clock::now() - t0 < std::chrono::seconds(20));
    CHECK(contains(run_softcut("mesh info --timeout -1 x.vtu", dir).output, "--timeout"));
  }
}
