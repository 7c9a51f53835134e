#include <doctest/doctest.h>

#include <fstream>
#include <string>

#include "app/commands.hpp"
#include "core/error.hpp"
#include "mesh/generate/presets.hpp"
#include "mesh/generate/band.hpp"
#include "mesh/io/mesh_io.hpp"
#include "sim/mesh_source.hpp"
#include "cli_test_support.hpp"
#include "test_support.hpp"

using namespace softcut;
namespace fs = std::filesystem;

namespace {

std::string error_of(const app::Args& args) {
  try {
    app::cmd_mesh(args);
  } catch (const Error& e) {
    return e.what();
  }
  return "(no error)";
}

}  // namespace

TEST_SUITE("app/cmd_mesh") {
  TEST_CASE("generate the paper presets, with hole nodes - info and convert read them back") {
    const fs::path dir = test::scratch_dir("cmd_mesh");
    const std::string lig = (dir / "lig.vtu").string(), leg = (dir / "leg.msh").string();
    const std::string hole = (dir / "hole.txt").string();
    REQUIRE(app::cmd_mesh({"generate", "ligament", lig}) == 0);
    REQUIRE(app::cmd_mesh({"generate", "upper_leg", "--hole-nodes", hole, leg}) == 0);
    Diagnostics d;
    const mesh::TetMesh a = mesh::read_mesh(lig, d), b = mesh::read_mesh(leg, d);
    CHECK(a.num_tets() == mesh::generate_band(mesh::ligament_preset()).num_tets());
    CHECK(b.num_nodes() == mesh::generate_tube(mesh::upper_leg_preset()).num_nodes());
    std::ifstream in(hole);
    std::string line;
    std::getline(in, line);
    CHECK(line.rfind("#", 0) == 0);
    std::vector<int> ids;
    for (int id; in >> id;) ids.push_back(id);
    CHECK(ids == mesh::tube_hole_nodes(b, mesh::upper_leg_preset()));
    CHECK(app::cmd_mesh({"info", leg, "--json"}) == 0);
    CHECK(app::cmd_mesh({"info", lig}) == 0);
    CHECK(app::cmd_mesh({"convert", leg, (dir / "leg.vtu").string()}) == 0);
    CHECK(mesh::read_mesh(dir / "leg.vtu", d).tets == b.tets);
  }

  TEST_CASE("generate options and the label volume path") {
    const fs::path dir = test::scratch_dir("cmd_mesh_opts");
    Diagnostics d;
    REQUIRE(app::cmd_mesh({"generate", "box", "--size", "0.1,0.2,0.3", "--cells=2,3,4", (dir / "b.vtu").string()}) == 0);
    const mesh::TetMesh box = mesh::read_mesh(dir / "b.vtu", d);
    CHECK(box.num_tets() == 6 * 24);
    CHECK(mesh::total_volume(box) == doctest::Approx(0.006));
    REQUIRE(app::cmd_mesh({"generate", "tube", "--cells", "2,10,3", "--label", "4", (dir / "t.vtu").string()}) == 0);
    CHECK(mesh::read_mesh(dir / "t.vtu", d).labels.maxCoeff() == 4);
    const std::string organ = (test::data_dir() / "volume" / "organ.nhdr").string();
    REQUIRE(app::cmd_mesh({"generate", "volume", organ, "--labels", "2", (dir / "v.vtu").string()}) == 0);
    CHECK(mesh::read_mesh(dir / "v.vtu", d).num_tets() == 6 * 36);
  }

  TEST_CASE("generate an organ and mesh a label volume with CGAL, options spelled as on the command line") {
    const fs::path dir = test::scratch_dir("cmd_mesh_cgal");
    Diagnostics d;
    REQUIRE(app::cmd_mesh({"generate", "kidney", "--target-tets", "2000", "--fine-center", "0,0,0.02", "--fine-radius",
                           "0.02", (dir / "k.vtu").string()}) == 0);
    const mesh::TetMesh k = mesh::read_mesh(dir / "k.vtu", d);
    CHECK(std::abs(k.num_tets() - 2000) <= 400);
    CHECK(k.labels.maxCoeff() == 2);
    const std::string organ = (test::data_dir() / "volume" / "organ.nhdr").string();
    REQUIRE(app::cmd_mesh({"generate", "volume", organ, "--mesher", "cgal", (dir / "v.vtu").string()}) == 0);
    CHECK(mesh::read_mesh(dir / "v.vtu", d).num_tets() > 0);
    CHECK(error_of({"generate", "liver", "--fine-center", "1,2", "x.vtu"}).find("expected 3 comma-separated") != std::string::npos);
    CHECK(error_of({"generate", "liver", "--lobes", "3", "x.vtu"}).find("unknown option '--lobes'") != std::string::npos);
    CHECK(error_of({"generate", "volume", organ, "--mesher", "tetgen", "x.vtu"}).find("--mesher tetgen not in {voxels,cgal}") != std::string::npos);
    CHECK(error_of({"generate", "volume", organ, "--mesher", "cgal", "--smooth", "2", "x.vtu"}).find("--smooth is for --mesher voxels") != std::string::npos);
  }

  TEST_CASE("generator options are the scenario's, spelled for the command line, with --size and --cells as shorthands") {
    const fs::path dir = test::scratch_dir("cmd_mesh_names");
    Diagnostics d;
    // The same box three ways: shorthands, the scenario's names, and s:mesh{} through the scenario's path.
    REQUIRE(app::cmd_mesh({"generate", "box", "--size", "0.1,0.2,0.3", "--cells", "2,3,4", "--jitter", "0.1",
                           (dir / "a.vtu").string()}) == 0);
    REQUIRE(app::cmd_mesh({"generate", "box", "--max", "0.1,0.2,0.3", "--nx", "2", "--ny=3", "--nz", "4", "--jitter",
                           "0.1", (dir / "b.vtu").string()}) == 0);
    sim::MeshSource src;
    src.generator = "box";
    src.options = {{"max.x", 0.1}, {"max.y", 0.2}, {"max.z", 0.3}, {"nx", 2}, {"ny", 3}, {"nz", 4}, {"jitter", 0.1}};
    const mesh::TetMesh a = mesh::read_mesh(dir / "a.vtu", d), b = mesh::read_mesh(dir / "b.vtu", d);
    const mesh::TetMesh c = sim::load_mesh_source(src, d).mesh;
    CHECK(a.tets == c.tets);
    CHECK(b.tets == c.tets);
    CHECK((a.nodes - c.nodes).cwiseAbs().maxCoeff() <= 1e-12);  // (through the file's text)
    CHECK((b.nodes - c.nodes).cwiseAbs().maxCoeff() <= 1e-12);
    // A preset's resolution yields to the cell counts asked for, on the command line and in a scenario alike.
    REQUIRE(app::cmd_mesh({"generate", "ligament", "--cells", "10,3,2", (dir / "l.vtu").string()}) == 0);
    mesh::BandOptions lig = mesh::ligament_preset();
    lig.target_tets = lig.target_nodes = 0;
    lig.along = 10, lig.across = 3, lig.through = 2;
    CHECK(mesh::read_mesh(dir / "l.vtu", d).num_tets() == mesh::generate_band(lig).num_tets());
    src.generator = "ligament";
    src.options = {{"along", 10}, {"across", 3}, {"through", 2}};
    CHECK(sim::load_mesh_source(src, d).mesh.num_tets() == mesh::generate_band(lig).num_tets());
    // One value, one option; an unknown one lists what the kind takes, as the command line spells it.
    CHECK(error_of({"generate", "box", "--cells", "2,2,2", "--nx", "3", "x.vtu"}).find("--cells and --nx both set nx") !=
          std::string::npos);
    const std::string e = error_of({"generate", "tube", "--max", "1,1,1", "x.vtu"});
    CHECK(e.find("unknown option '--max'") != std::string::npos);
    CHECK(e.find("--inner-radius") != std::string::npos);
    CHECK(e.find("--base-center X,Y,Z") != std::string::npos);
    CHECK(e.find("--cells") != std::string::npos);
  }

  TEST_CASE("bad input: one-line reasons") {
    CHECK(error_of({"frob"}).find("unknown subcommand 'frob'") != std::string::npos);
    CHECK(error_of({"generate", "sphere", "x.vtu"}).find("unknown kind 'sphere'") != std::string::npos);
    CHECK(error_of({"generate", "box", "--cells", "2,2", "x.vtu"}).find("expected 3 comma-separated") !=
          std::string::npos);
    CHECK(error_of({"generate", "cylinder", "--target-tets", "1.5", "x.vtu"}).find("expected an integer") !=
          std::string::npos);
    CHECK(error_of({"generate", "band", "--bogus", "1", "x.vtu"}).find("unknown option '--bogus'") != std::string::npos);
    CHECK(error_of({"generate", "box", "--hole-nodes", "h", "x.vtu"}).find("unknown option '--hole-nodes'") != std::string::npos);
    CHECK(error_of({"generate", "volume", "x.vtu"}).find("expected IN.nrrd") != std::string::npos);
    CHECK(error_of({"info"}).find("softcut mesh info: file is required") != std::string::npos);
    CHECK(error_of({"info", "/nonexistent/x.vtu"}).find("/nonexistent/x.vtu") != std::string::npos);
    CHECK(error_of({"convert", "a.vtu"}).find("softcut mesh convert: out is required") != std::string::npos);
    for (const std::string& e : {error_of({"generate", "tube", "--jitter", "0.5", "x.vtu"})})
      CHECK(e.find('\n') == std::string::npos);
  }

  TEST_CASE("mesh info --json is valid JSON that describes the mesh, whatever bytes the file name holds") {
    const fs::path dir = test::scratch_dir("cmd_mesh_info_json");
    const fs::path file = dir / "b\"ox\xE9.vtu";  // a quote and a byte that is not UTF-8
    REQUIRE(app::cmd_mesh({"generate", "box", "--size", "0.1,0.2,0.3", "--cells=2,3,4", file.string()}) == 0);
    const auto r = test::run_cli_raw("('" SOFTCUT_BIN "' mesh info '" + file.string() + "' --json 2>/dev/null)");
    REQUIRE(r.status == 0);
    const nlohmann::ordered_json j = test::parse_json(r.output);
    CHECK(j.at("file") == (dir / "b\"ox\xEF\xBF\xBD.vtu").string());  // U+FFFD for the stray byte
    CHECK(j.at("tets") == 6 * 24);
    CHECK(j.at("nodes") == 3 * 4 * 5);
    CHECK(j.at("referenced_nodes") == 60);
    CHECK(j.at("interior_nodes") == 60 - j.at("surface_nodes").get<int>());
    CHECK(j.at("labels").size() == 1);
    CHECK(j.at("labels").at(0).at("tets") == 144);
    CHECK(j.at("bbox_min") == nlohmann::ordered_json{0.0, 0.0, 0.0});
    CHECK(j.at("bbox_max") == nlohmann::ordered_json{0.1, 0.2, 0.3});
    CHECK(j.at("volume").get<double>() == doctest::Approx(0.006));
    CHECK(j.at("surface").at("closed_manifold") == true);
    CHECK(j.at("surface").at("euler") == 2);
    CHECK(j.at("quality").at("poor") == 0);
    CHECK(j.at("warnings").empty());
  }
}

TEST_SUITE("app/cmd_mesh") {
  TEST_CASE("units: info warns on an implausible size and --unit fixes it - convert --unit/--scale write metres - an organ at --scale 1000") {
    const fs::path dir = test::scratch_dir("cmd_mesh_units");
    const std::string mm = (dir / "box_mm.vtu").string();
    REQUIRE(app::cmd_mesh({"generate", "box", "--size", "190,130,80", mm}) == 0);  // a liver's box, in mm
    auto r = test::run_cli("mesh info '" + mm + "'");
    CHECK(r.status == 0);
    CHECK(test::contains(r.output, "the body is 190 m across"));
    CHECK(test::contains(r.output, "unit = \"mm\""));
    CHECK(test::contains(r.output, "[implausible_size]"));
    r = test::run_cli("mesh info '" + mm + "' --unit mm --json");
    CHECK(!test::contains(r.output, "implausible_size"));
    CHECK(test::contains(r.output, "0.19"));
    Diagnostics d;
    REQUIRE(app::cmd_mesh({"convert", mm, (dir / "a.vtu").string(), "--unit", "mm"}) == 0);
    CHECK(mesh::read_mesh(dir / "a.vtu", d).nodes.col(0).maxCoeff() == doctest::Approx(0.19));
    REQUIRE(app::cmd_mesh({"convert", mm, (dir / "b.vtu").string(), "--scale", "0.001"}) == 0);
    CHECK(mesh::read_mesh(dir / "b.vtu", d).nodes.col(0).maxCoeff() == doctest::Approx(0.19));
    CHECK(error_of({"convert", mm, "c.vtu", "--unit", "inch"}).find("--unit inch not in") != std::string::npos);
    // Refused before as "scale must be in (0, 1000)": a liver in millimetres.
    REQUIRE(app::cmd_mesh({"generate", "liver", "--scale", "1000", "--target-tets", "1000", (dir / "liver_mm.vtu").string()}) == 0);
    CHECK(mesh::read_mesh(dir / "liver_mm.vtu", d).nodes.col(0).maxCoeff() > 50);
  }

  TEST_CASE("generate surface: closed surfaces to labelled tets, the unit guessed and said, a bad surface named") {
    const fs::path dir = test::scratch_dir("cmd_mesh_surface");
    const std::string outer = (test::data_dir() / "surface" / "outer_mm.off").string();
    const std::string inner = (test::data_dir() / "surface" / "inner_mm.obj").string();
    const auto r = test::run_cli("mesh generate surface '" + outer + "' '" + inner + "' --target-tets 2000 '" + (dir / "n.vtu").string() + "'");
    CHECK(r.status == 0);
    CHECK(test::contains(r.output, "taken as mm from their size"));
    CHECK(test::contains(r.output, "[unit_guessed]"));
    Diagnostics d;
    const mesh::TetMesh m = mesh::read_mesh(dir / "n.vtu", d);
    CHECK(m.labels.minCoeff() == 1);
    CHECK(m.labels.maxCoeff() == 2);
    CHECK(m.nodes.col(0).maxCoeff() == doctest::Approx(0.04).epsilon(0.02));
    REQUIRE(app::cmd_mesh({"generate", "surface", outer, "--unit", "mm", "--cell-size", "0.008", (dir / "o.vtu").string()}) == 0);
    // An open surface: the first 100 faces of the sphere only.
    std::ifstream in(outer);
    std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    text.replace(text.find("642 1280 0"), 10, "642 100 0");
    std::ofstream(dir / "open.off") << text;
    CHECK(error_of({"generate", "surface", (dir / "open.off").string(), "x.vtu"}).find("the surface is not closed") != std::string::npos);
    CHECK(error_of({"generate", "surface", "x.vtu"}).find("expected IN.stl [IN2 ...] and OUT") != std::string::npos);
    CHECK(error_of({"generate", "surface", (dir / "x.vrml").string(), "x.vtu"}).find("unknown surface file extension") != std::string::npos);
  }

  TEST_CASE("--help is generated from the declarations: each kind's options with their defaults") {
    auto r = test::run_cli("mesh generate tube --help");
    CHECK(r.status == 0);
    CHECK(test::contains(r.output, "--inner-radius"));
    CHECK(test::contains(r.output, "radius of the hole, m (0.012)"));
    CHECK(test::contains(r.output, "--hole-nodes"));
    CHECK(test::contains(r.output, "--timeout"));
    r = test::run_cli("mesh generate surface --help");
    CHECK(test::contains(r.output, "--unit"));
    CHECK(test::contains(r.output, "--fine-center"));
    CHECK(test::contains(test::run_cli("mesh generate --help").output, "surface"));
    CHECK(test::contains(test::run_cli("mesh info --help").output, "--max-memory"));
  }
}
