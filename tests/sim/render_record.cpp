#include "sim/render_record.hpp"
#include "sim/render_record_meta.hpp"

#include <doctest/doctest.h>

#include <random>

#include "fixtures.hpp"
#include "sim/frame_scene.hpp"
#include "sim/step.hpp"
#include "test_support.hpp"

namespace fs = std::filesystem;
namespace sim = softcut::sim;
namespace render = softcut::render;
namespace tools = softcut::tools;
using V = Eigen::Vector3d;

namespace {

// A bar cut through by a scalpel while a probe presses it: the topology
// changes mid-run, tools come and go.
sim::ScenarioSpec cut_bar(const fs::path& dir) {
  sim::ScenarioSpec s = softcut::test::held_bar_spec("record_bar", V(0.1, 0.02, 0.02), 5e3, 0.03, 0.07, true);
  sim::MaterialAssignment second;
  second.name = "second";
  second.young = 8e3;
  second.poisson = 0.4;
  second.tets.kind = sim::TetSelector::Kind::box;
  second.tets.min = V(0.06, -1, -1);
  second.tets.max = V(1, 1, 1);
  s.materials.push_back(second);
  auto blade = softcut::test::cutting_blade(V(0, 1, 0), V(0, 0, -1));
  blade.blade_length = 0.04;
  blade.radius = 0.0015;
  blade.cut_pressure = 1000;
  blade.force = tools::Ramp::linear_ramp(0.0, 0.2, 0.0, 0.2);
  blade.path = tools::Path::polyline({0.0, 0.3, 1.0}, {V(0.0512, 0.01, 0.0205), V(0.0512, 0.01, 0.0205), V(0.0512, 0.01, -0.004)});
  s.tools.push_back(blade);
  tools::ToolSpec probe;
  probe.name = "probe";
  probe.radius = 0.004;
  probe.force = tools::Ramp::constant_value(0.01);
  probe.path = tools::Path::polyline({0.0, 1.0}, {V(0.08, 0.01, 0.0235), V(0.08, 0.01, 0.0225)});
  probe.start = 0.2;
  s.tools.push_back(probe);
  s.timeline.duration = 0.6;
  s.timeline.fps = 20.0;
  s.outputs.dir = dir;
  s.outputs.render.enabled = true;
  s.outputs.render.width = 64, s.outputs.render.height = 48;
  s.outputs.render.record = sim::RenderSettings::Record::on;
  s.outputs.render.show_forces = true;
  return s;
}

// The run's own scenes, and the record written beside them.
struct Recorded {
  std::vector<render::Scene> scenes;
  std::string bytes;
  int cuts = 0;
};

Recorded record(const sim::ScenarioSpec& spec, const fs::path& dir) {
  const sim::Model m = sim::compile(spec);
  sim::State s = sim::make_state(m);
  Recorded r;
  {
    sim::RenderRecordWriter w(dir, sim::render_record_meta(m));
    render::SceneExtractor extractor;
    while (s.frame < m.num_frames - 1) {
      sim::step(m, s);
      const auto& mesh = sim::current_mesh(m, s);
      const Eigen::MatrixX3d x = sim::deformed_positions(m, s);
      const render::SceneContent c = sim::scene_content(m, s);
      const render::RenderSettings rs = sim::render_settings(m, s);
      r.scenes.push_back(extractor.extract(mesh, x, c, rs));
      w.add(s.frame, s.time, mesh, x, c, rs.camera);
    }
    w.finish();
  }
  r.cuts = int(s.cut_events.size());
  r.bytes = softcut::test::slurp(dir / sim::kRenderRecordFile);
  return r;
}

bool same(const render::Triangles& a, const render::Triangles& b) {
  return a.positions == b.positions && a.normals == b.normals && a.colors == b.colors && a.labels == b.labels;
}
bool same(const render::Primitives& a, const render::Primitives& b) {
  return a.positions == b.positions && a.colors == b.colors;
}

}  // namespace

TEST_SUITE("sim/render_record") {
  TEST_CASE("a record redraws every frame's scene exactly, across cuts") {
    const fs::path dir = softcut::test::scratch_dir("render_record_round");
    const sim::ScenarioSpec spec = cut_bar(dir);
    const Recorded run = record(spec, dir);
    REQUIRE(run.cuts > 0);  // the topology changed during the run
    sim::RenderRecordReader reader(run.bytes, "record");
    const sim::RecordMeta meta = sim::parse_record_meta(reader.meta(), "record");
    CHECK(meta.scenario == "record_bar");
    CHECK(meta.render.width == 64);
    sim::RecordFrame f;
    Eigen::MatrixX3d x;
    render::SceneContent c;
    render::SceneExtractor extractor;
    std::size_t i = 0;
    int topologies = 0;
    while (reader.next(f)) {
      REQUIRE(i < run.scenes.size());
      topologies = std::max(topologies, f.topology + 1);
      const sim::RecordTopology& topo = reader.topology(f.topology);
      sim::scene_inputs(topo, f, x, c);
      const render::Scene s =
          extractor.extract(topo.mesh, x, c, sim::render_settings(meta.render, meta.palette, f.camera));
      const render::Scene& want = run.scenes[i];
      CAPTURE(i);
      CHECK(same(s.tissue, want.tissue));
      CHECK(same(s.wound, want.wound));
      CHECK(same(s.tools, want.tools));
      CHECK(same(s.inclusions, want.inclusions));
      CHECK(same(s.outline, want.outline));
      CHECK(same(s.force_lines, want.force_lines));
      CHECK(same(s.manipulated_points, want.manipulated_points));
      CHECK(s.camera.view == want.camera.view);
      CHECK(s.camera.projection == want.camera.projection);
      ++i;
    }
    CHECK(i == run.scenes.size());
    CHECK(reader.frames_read() == int(i));
    CHECK(topologies >= 2);
  }

  TEST_CASE("a record cut short, corrupted or lying about its sizes is refused with an Error, never a crash") {
    const fs::path dir = softcut::test::scratch_dir("render_record_bad");
    auto spec = cut_bar(dir);
    spec.timeline.duration = 0.4;
    const std::string good = record(spec, dir).bytes;
    REQUIRE(good.size() > 100);
    auto read_all = [](const std::string& bytes) {
      sim::RenderRecordReader r(bytes, "bad.bin");
      sim::parse_record_meta(r.meta(), "bad.bin");
      sim::RecordFrame f;
      while (r.next(f)) {
      }
    };
    CHECK_NOTHROW(read_all(good));
    // Every cut-short prefix (the run killed while writing) fails.
    int refused = 0;
    for (std::size_t n = 0; n < good.size(); n += std::max<std::size_t>(1, good.size() / 400)) {
      const std::string msg = softcut::test::error_of([&] { read_all(good.substr(0, n)); });
      refused += !msg.empty();
      CHECK_MESSAGE(!msg.empty(), "a prefix of ", n, " bytes was read as a whole record");
    }
    CHECK(refused > 100);
    // Flipped bytes: refused by the checksums or the bounds (or harmless).
    std::mt19937 rng(7);
    for (int k = 0; k < 300; ++k) {
      std::string bad = good;
      bad[rng() % bad.size()] ^= char(1 + rng() % 255);
      (void)softcut::test::error_of([&] { read_all(bad); });
    }
    // A chunk claiming a huge inflated size is refused before anything is allocated.
    std::string huge = good;
    const std::size_t head = 22 + 4;  // magic, version: then the meta chunk's kind, packed and raw sizes
    const std::uint64_t lie = std::uint64_t(1) << 40;
    std::memcpy(huge.data() + head + 9, &lie, 8);
    CHECK(softcut::test::contains(softcut::test::error_of([&] { read_all(huge); }), "more than the limit"));
    CHECK(softcut::test::contains(softcut::test::error_of([&] { read_all("not a record"); }),
                                  "not a softcut render record"));
  }
}
