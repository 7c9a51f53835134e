#include "sim/outputs.hpp"

#include <doctest/doctest.h>

#include <fstream>
#include <set>
#include <sstream>

#include "fixtures.hpp"
#include "gl/egl_context.hpp"
#include "render/contact_sheet.hpp"
#include "render/frame_writer.hpp"
#include "render/image.hpp"
#include "mesh/io/mesh_io.hpp"
#include "sim/step.hpp"
#include "test_support.hpp"

namespace fs = std::filesystem;
namespace sim = softcut::sim;

using softcut::test::slurp;

namespace {

// The cantilever with small frames, no MSAA: rendering without the cost.
sim::ScenarioSpec rendering_cantilever_spec(const fs::path& dir, double duration) {
  auto spec = softcut::test::cantilever_spec(dir, duration);
  spec.outputs.render.enabled = true;
  spec.outputs.render.width = 48;
  spec.outputs.render.height = 32;
  spec.outputs.render.msaa_samples = 0;
  return spec;
}

}  // namespace

TEST_SUITE("sim/outputs") {
  TEST_CASE("CSV rows round-trip the displacements of the log nodes at %.9e") {
    const fs::path dir = softcut::test::scratch_dir("sim_outputs_csv");
    auto spec = softcut::test::cantilever_spec(dir, 0.1);
    spec.outputs.log_all_surface = false;
    spec.outputs.log_nodes = sim::NodeSelector::list({5, 17});
    const sim::Model m = sim::compile(spec);
    sim::State s = sim::make_state(m);
    sim::Recorder rec(m, dir);
    sim::step(m, s);
    sim::step(m, s);
    rec.record(m, s);
    CHECK(fs::exists(dir / "displacements.csv.partial"));
    CHECK(!fs::exists(dir / "displacements.csv"));
    rec.finish(m, s, sim::RunResult{});
    std::istringstream in(slurp(dir / "displacements.csv"));
    std::string line;
    std::getline(in, line);
    for (int n : {5, 17}) {
      REQUIRE(std::getline(in, line));
      int frame = -1, node = -1;
      double t, u[3];
      REQUIRE(std::sscanf(line.c_str(), "%d,%lf,%d,%lf,%lf,%lf", &frame, &t, &node, &u[0], &u[1], &u[2]) == 6);
      CHECK(frame == 1);
      CHECK(node == n);
      CHECK(t == doctest::Approx(0.1).epsilon(1e-9));
      for (int a = 0; a < 3; ++a)
        CHECK(std::abs(u[a] - s.displacement(n, a)) <= 1e-9 * std::abs(s.displacement(n, a)) + 1e-300);
    }
    CHECK(!std::getline(in, line));
  }

  TEST_CASE("VTU per frame and a PVD series: the VTU reads back with the same mesh") {
    const fs::path dir = softcut::test::scratch_dir("sim_outputs_vtu");
    auto spec = softcut::test::cantilever_spec(dir, 0.3);
    spec.outputs.vtu = true;
    spec.outputs.vtu_every = 2;
    const sim::Model m = sim::compile(spec);
    sim::State s = sim::make_state(m);
    sim::Recorder rec(m, dir);
    sim::RunHooks hooks;
    const sim::RunResult r = sim::run(m, s, rec, hooks);
    CHECK(r.frames == 4);
    CHECK(fs::exists(dir / "vtu" / "frame_000000.vtu"));
    CHECK(!fs::exists(dir / "vtu" / "frame_000001.vtu"));
    CHECK(fs::exists(dir / "vtu" / "frame_000002.vtu"));
    const std::string pvd = slurp(dir / "series.pvd");
    CHECK(pvd.find("file=\"vtu/frame_000002.vtu\"") != std::string::npos);
    CHECK(pvd.find("timestep=\"0.2\"") != std::string::npos);
    const std::string vtu = slurp(dir / "vtu" / "frame_000002.vtu");
    CHECK(vtu.find("Name=\"displacement\"") != std::string::npos);
    softcut::Diagnostics diag;
    const softcut::mesh::TetMesh back = softcut::mesh::read_mesh(dir / "vtu" / "frame_000002.vtu", diag);
    CHECK(back.num_nodes() == m.mesh.num_nodes());
    CHECK(back.num_tets() == m.mesh.num_tets());
    CHECK((back.nodes - m.mesh.nodes).norm() < 1e-9);
  }

  TEST_CASE("a frame writer writes every n-th frame as PNG, the same pixels inline and on its worker") {
    using Mode = softcut::render::FrameWriter::Mode;
    const fs::path root = softcut::test::scratch_dir("sim_outputs_render");
    softcut::gl::EglContext ctx;
    for (const Mode mode : {Mode::inline_draw, Mode::worker}) {
      const bool worker = mode == Mode::worker;
      const fs::path dir = root / (worker ? "worker" : "inline");
      auto spec = rendering_cantilever_spec(dir, 0.3);
      spec.outputs.render.every = 2;
      const sim::Model m = sim::compile(spec);
      softcut::render::FrameWriter writer(ctx, mode);
      sim::State s = sim::make_state(m);
      sim::Recorder rec(m, dir);
      rec.set_frame_writer(&writer);
      sim::run(m, s, rec, {});
      CHECK(fs::exists(dir / "frames" / "frame_000000.png"));
      CHECK(!fs::exists(dir / "frames" / "frame_000001.png"));
      CHECK(fs::exists(dir / "frames" / "frame_000002.png"));
      CHECK(rec.frames_rendered() == 2);
      CHECK(writer.stats().frames == 2);
      const std::string summary = slurp(dir / "summary.json");
      CHECK(summary.find("\"frames_rendered\": 2") != std::string::npos);
      CHECK(summary.find(worker ? "\"render_mode\": \"worker\"" : "\"render_mode\": \"inline\"") != std::string::npos);
    }
    for (const char* f : {"frame_000000.png", "frame_000002.png"}) {
      const auto a = softcut::render::read_png(root / "inline" / "frames" / f);
      const auto b = softcut::render::read_png(root / "worker" / "frames" / f);
      CHECK_MESSAGE(a.rgba == b.rgba, f);
    }
  }

  TEST_CASE("a frame that cannot be written fails the run after the summary is written, in both writer modes") {
    using Mode = softcut::render::FrameWriter::Mode;
    softcut::gl::EglContext ctx;
    for (const Mode mode : {Mode::inline_draw, Mode::worker}) {
      const fs::path dir = softcut::test::scratch_dir(mode == Mode::worker ? "sim_outputs_fail_w" : "sim_outputs_fail_i");
      fs::create_directories(dir / "frames" / "frame_000002.png");  // a folder where frame 2 goes
      auto spec = rendering_cantilever_spec(dir, 0.4);
      const sim::Model m = sim::compile(spec);
      softcut::render::FrameWriter writer(ctx, mode);
      sim::State s = sim::make_state(m);
      sim::Recorder rec(m, dir);
      rec.set_frame_writer(&writer);
      bool threw = false;
      try {
        sim::run(m, s, rec, {});
      } catch (const softcut::Error& e) {
        threw = true;
        CHECK(std::string(e.what()).find("frame_000002.png") != std::string::npos);
      }
      CHECK(threw);
      const std::string summary = slurp(dir / "summary.json");
      CHECK(summary.find("\"exit_reason\": \"error\"") != std::string::npos);
      CHECK(summary.find("frame_000002.png") != std::string::npos);
      CHECK(!fs::exists(dir / "contact_sheet.png"));
      CHECK(fs::exists(dir / "frames" / "frame_000001.png"));
    }
  }

  TEST_CASE("a run owns its output folder: an earlier run's files go, other files and link targets stay") {
    const fs::path root = softcut::test::scratch_dir("sim_outputs_owned");
    const fs::path dir = root / "out";
    softcut::gl::EglContext ctx;
    auto run_once = [&](double duration) {
      auto spec = rendering_cantilever_spec(dir, duration);
      spec.outputs.vtu = true;
      const sim::Model m = sim::compile(spec);
      softcut::render::FrameWriter writer(ctx, softcut::render::FrameWriter::Mode::inline_draw);
      sim::State s = sim::make_state(m);
      sim::Recorder rec(m, dir);
      rec.set_frame_writer(&writer);
      sim::run(m, s, rec, {});
      return rec.frames_rendered();
    };
    auto names = [](const fs::path& d) {
      std::set<std::string> out;
      for (const auto& e : fs::directory_iterator(d)) out.insert(e.path().filename().string());
      return out;
    };
    const int long_frames = run_once(0.9);  // frames 0..9
    REQUIRE(long_frames > 4);
    REQUIRE(fs::exists(dir / "frames" / "frame_000009.png"));
    // What a user or an earlier, killed run left: kept unless softcut names it.
    const softcut::render::Image odd(7, 3, 0xff00ffffu);
    softcut::render::write_png(dir / "frames" / "frame_extra.png", odd);  // not a frame name: kept, not on the sheet
    std::ofstream(dir / "notes.txt") << "mine";
    std::ofstream(dir / ".summary.json.123.4.tmp") << "stale temporary";
    std::ofstream(dir / "vtu" / "frame_000123.vtu.bak") << "mine too";
    std::ofstream(root / "target.txt") << "outside";
    fs::remove(dir / "series.pvd");
    fs::create_symlink(root / "target.txt", dir / "series.pvd");  // unlinked, never written through

    const int short_frames = run_once(0.3);  // frames 0..3
    CHECK(short_frames == 4);
    std::set<std::string> frames = names(dir / "frames");
    CHECK(frames == std::set<std::string>{"frame_000000.png", "frame_000001.png", "frame_000002.png",
                                          "frame_000003.png", "frame_extra.png"});
    const std::set<std::string> vtus = names(dir / "vtu");
    CHECK(vtus.size() == 5);
    CHECK(vtus.count("frame_000123.vtu.bak") == 1);
    CHECK(vtus.count("frame_000009.vtu") == 0);
    CHECK(slurp(dir / "notes.txt") == "mine");
    CHECK(!fs::exists(dir / ".summary.json.123.4.tmp"));
    CHECK(slurp(root / "target.txt") == "outside");
    CHECK(!fs::is_symlink(dir / "series.pvd"));
    const std::string pvd = slurp(dir / "series.pvd");
    CHECK(pvd.find("frame_000003.vtu") != std::string::npos);
    CHECK(pvd.find("frame_000004.vtu") == std::string::npos);
    // The sheet holds this run's four frames only: a 2 x 2 grid (five would be 3 x 2).
    const softcut::render::Image sheet = softcut::render::read_png(dir / "contact_sheet.png");
    const softcut::render::ContactSheetOptions o;
    CHECK(sheet.width == o.gap + 2 * (o.tile_width + o.gap));

    // A third run without rendering or VTU leaves neither folder behind, only the user's files.
    fs::remove(dir / "frames" / "frame_extra.png");
    fs::remove(dir / "vtu" / "frame_000123.vtu.bak");
    {
      auto spec = softcut::test::cantilever_spec(dir, 0.1);
      const sim::Model m = sim::compile(spec);
      sim::State s = sim::make_state(m);
      sim::Recorder rec(m, dir);
      sim::run(m, s, rec, {});
    }
    CHECK(names(dir) == std::set<std::string>{"displacements.csv", "notes.txt", "summary.json", "validity.csv"});
  }

  TEST_CASE("summary.json carries the schema fields") {
    const fs::path dir = softcut::test::scratch_dir("sim_outputs_summary");
    auto spec = softcut::test::cantilever_spec(dir, 0.1);
    spec.versions["lua"] = "Lua 5.4";
    spec.name = "bar \"quoted\"";
    const sim::Model m = sim::compile(spec);
    sim::State s = sim::make_state(m);
    sim::step(m, s);
    const std::string text = sim::summary_json(m, s, sim::RunResult{});
    const nlohmann::ordered_json j = softcut::test::parse_json(text);
    CHECK(j["schema"] == "softcut-summary/1");
    CHECK(j["scenario"]["name"] == "bar \"quoted\"");
    CHECK(softcut::test::contains(text, "\"bar \\\"quoted\\\"\""));  // escaped in the text
    CHECK(j["versions"]["lua"] == "Lua 5.4");
    CHECK(j["partition"]["operational_tets"] == 24);
    CHECK(j["precompute_ms"].is_object());
    CHECK(j["stage_ms"]["operational_solve"]["mean"].is_number());
    CHECK(j["cg"].is_object());
    CHECK(j["run"]["interrupted"] == false);
    CHECK(j["warnings"].is_array());
    // The keys in the documented order (docs/summary-schema.md).
    std::vector<std::string> keys;
    for (const auto& [k, v] : j.items()) keys.push_back(k);
    CHECK(keys == std::vector<std::string>{"schema", "scenario", "versions", "command_line", "params", "mesh",
                                           "partition", "solver", "precompute_ms", "precompute_cache", "threads",
                                           "columns", "timeline", "run", "limits", "stage_ms", "springs", "cg",
                                           "newton", "validity", "outputs", "tools", "cutting", "expectations",
                                           "metrics", "warnings"});
    CHECK(j["metrics"].is_array());
    CHECK(j["metrics"].empty());  // nothing recorded
    CHECK(j["newton"]["frames"] == 0);  // a linear run
    CHECK(j["validity"]["linear_strain_max"].is_number());
    CHECK(j["validity"]["bounds"]["condensed_rotation_deg"] == 10.0);
  }
}
