// Every input in tests/fuzz/regressions/<target>/ (crashes the fuzzers found,
// kept after the fix) goes through the normal build's entry points, the way a
// user's file would: it must read cleanly or fail with softcut::Error.
#include <doctest/doctest.h>

#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "../fuzz/app_fuzz.hpp"
#include "hardening_support.hpp"
#include "mesh/io/mesh_io.hpp"
#include "mesh/io/surface_io.hpp"
#include "mesh/mesher/surface_domain.hpp"
#include "mesh/volume/label_volume.hpp"
#include "mesh/volume/nrrd.hpp"
#include "scenario_script.hpp"  // lua/
#include "../fuzz/render_record_fuzz.hpp"

namespace fs = std::filesystem;
using softcut::hardening::put_file;

using softcut::test::slurp;

namespace {

std::vector<fs::path> inputs(const std::string& target, const char* folder = "regressions") {
  std::vector<fs::path> v;
  std::error_code ec;
  for (const auto& e : fs::directory_iterator(fs::path(SOFTCUT_FUZZ_REGRESSIONS).parent_path() / folder / target, ec))
    if (e.is_regular_file() && e.path().filename().string()[0] != '.') v.push_back(e.path());
  std::sort(v.begin(), v.end());
  return v;
}

// Feeds one input the way its fuzz target does (see tests/fuzz/fuzz_<target>.cpp).
void feed(const std::string& target, const std::string& bytes, const fs::path& dir) {
  softcut::Diagnostics diag;
  if (target == "tetgen") {
    const std::size_t cut = bytes.find('\0');
    put_file(dir / "in.node", bytes.substr(0, cut));
    put_file(dir / "in.ele", cut == std::string::npos ? "" : bytes.substr(cut + 1));
    softcut::mesh::read_mesh(dir / "in.node", diag);
  } else if (target == "nrrd") {
    const auto v = softcut::mesh::read_nrrd_labels(put_file(dir / "in.nrrd", bytes), diag);
    if (v.num_voxels() <= 256) {
      softcut::mesh::VoxelMeshOptions opt;
      opt.smooth_iterations = 1;
      softcut::mesh::mesh_label_volume(v, opt, diag);
    }
  } else if (target == "render_record") {
    softcut::fuzz::read_render_record(bytes);
  } else if (target == "lua") {
    softcut::lua::ScriptRequest req;
    req.scenario = put_file(dir / "scenario.lua", bytes);
    req.sandbox.instruction_budget = 100'000;  // the fuzz target's budgets
    req.sandbox.memory_budget = 8u << 20;
    softcut::lua::open_scenario(req)->spec();
  } else if (target == "stl" || target == "obj" || target == "ply" || target == "off") {
    const auto s = softcut::mesh::read_surface(put_file(dir / ("in." + target), bytes), diag);
    if (s.triangles.rows() <= 4000) softcut::mesh::surface_domain({s}, 1.0, diag);
  } else if (target == "junit") {
    softcut::fuzz_app::feed_junit(bytes);
  } else if (target == "reflog") {
    softcut::fuzz_app::feed_reflog(bytes, dir);
  } else if (target == "sweep_table") {
    softcut::fuzz_app::feed_sweep_table(bytes, dir);
  } else if (target == "sweep_plan") {
    softcut::fuzz_app::feed_sweep_plan(bytes);
  } else if (target == "summary") {
    softcut::fuzz_app::feed_summary(bytes);
  } else {
    const char* ext = target == "gmsh" ? ".msh" : target == "medit" ? ".mesh" : target == "vtk" ? ".vtk" : ".vtu";
    softcut::mesh::read_mesh(put_file(dir / (std::string("in") + ext), bytes), diag);
  }
}

}  // namespace

TEST_SUITE("hardening/fuzz_regressions") {
  TEST_CASE("every saved fuzz finding reads cleanly or fails with softcut::Error") {
    const fs::path dir = softcut::test::scratch_dir("hardening_fuzz_regressions");
    int n = 0;
    for (const std::string target : {"gmsh", "medit", "vtk", "vtu", "tetgen", "nrrd", "stl", "obj", "ply", "off", "lua",
                                     "junit", "reflog", "sweep_table", "sweep_plan", "summary", "render_record"})
      for (const fs::path& p : inputs(target)) {
        CAPTURE(p.string());
        ++n;
        try {
          feed(target, slurp(p), dir);
        } catch (const softcut::Error&) {
        }
      }
    MESSAGE(n, " saved fuzz inputs replayed");
  }

  TEST_CASE("the application targets' seeds go through their entry points (JUnit writer, readers)") {
    // The targets are built only by the fuzz preset: this runs their code in every build.
    const fs::path dir = softcut::test::scratch_dir("hardening_fuzz_app_seeds");
    int n = 0;
    for (const std::string target : {"junit", "reflog", "sweep_table", "sweep_plan", "summary"}) {
      const std::vector<fs::path> seeds = inputs(target, "corpus");
      CHECK(seeds.size() >= 2);
      for (const fs::path& p : seeds) {
        CAPTURE(p.string());
        ++n;
        CHECK_NOTHROW(feed(target, slurp(p), dir));
      }
    }
    MESSAGE(n, " seeds of the application targets replayed");
  }
}
