// softcut bench springs: the cost of implicit grasper springs per frame
// (tools/springs.hpp) against the explicit spring, with and without the
// compliance cache, measured in the same run on a box of about 800 nodes.
#include <cstdio>
#include <filesystem>
#include <string>

#include "bench/bench.hpp"
#include "app/option_values.hpp"
#include "app/options.hpp"
#include "app/run_support.hpp"
#include "core/error.hpp"
#include "core/timer.hpp"
#include "sim/model.hpp"
#include "sim/step.hpp"

namespace softcut::bench {

namespace {

using V = Eigen::Vector3d;

// 0.1 x 0.04 x 0.04 m box (15 x 6 x 6 cells), fixed at x = 0, operational
// slab 0.04 <= x <= 0.07; a load on the free end grows to 0.05 N down while a
// grasper on the top face pulls up 5 mm over the run.
sim::ScenarioSpec bench_spec(const std::string& backend, double radius, double stiffness, int frames) {
  sim::ScenarioSpec s;
  s.name = "bench_springs";
  s.mesh.generator = "box";
  s.mesh.options = {{"max.x", 0.1}, {"max.y", 0.04}, {"max.z", 0.04}, {"nx", 15}, {"ny", 6}, {"nz", 6}};
  sim::MaterialAssignment mat;
  mat.name = "tissue";
  mat.young = 5e3;
  mat.poisson = 0.45;
  s.materials.push_back(mat);
  s.operational = sim::TetSelector::of(sim::TetSelector::Kind::box);
  s.operational.min = V(0.04, -1, -1);
  s.operational.max = V(0.07, 1, 1);
  s.fixed = sim::NodeSelector::box(V(-1, -1, -1), V(0, 1, 1));
  sim::LoadSpec end;
  end.name = "end";
  end.nodes = sim::NodeSelector::box(V(0.1, -1, -1), V(0.1, 1, 1));
  end.magnitude = tools::Ramp::linear_ramp(0.0, 0.05, 0.0, 1.0);
  s.loads.push_back(end);
  tools::ToolSpec g;
  g.name = "jaw";
  g.kind = tools::ToolSpec::Kind::grasper;
  g.drive = tools::ToolSpec::Drive::spring;
  g.radius = radius;
  g.stiffness = stiffness;
  const V p(0.08, 0.02, 0.04);
  g.path = tools::Path::polyline({0.0, 1.0}, {p, p + V(0, 0, 5e-3)});
  s.tools.push_back(g);
  s.timeline.duration = 1.0;
  s.timeline.fps = frames - 1;
  s.outputs.csv = false;
  s.solver.backend = backend::parse_backend(backend);
  return s;
}

struct Row {
  double frame_ms = 0, springs_ms = 0, build_ms = 0;
  int builds = 0, grasped = 0;
};

Row measure(const sim::Model& m, bool implicit, bool cache) {
  sim::State s = sim::make_state(m);
  s.tool_specs[0].implicit = implicit;
  s.springs.enabled = cache;
  Timer t;
  for (int f = 0; f < m.num_frames; ++f) sim::step(m, s);
  Row r;
  r.frame_ms = t.ms() / m.num_frames;
  r.springs_ms = (s.stats.springs.sum - s.springs.build_ms) / m.num_frames;
  r.build_ms = s.springs.build_ms;
  r.builds = s.springs.builds;
  r.grasped = int(s.tools[0].nodes.size());
  return r;
}

}  // namespace

int bench_springs(const Args& args) {
  app::Options o("softcut bench springs", "Steps a grasped box with an explicit spring, an implicit spring with the "
                 "compliance cache, and without it.");
  int frames = 31;
  double radius = 0.009;
  o.app().add_option("--frames", frames, "frames (default 31; at least 2)")->type_name("N")
      ->check(app::whole_number(0, 100000000));
  o.app().add_option("--radius", radius, "grasper radius in m (default 0.009: a grip on 17 nodes)")->type_name("R")
      ->check(app::open_interval(0, 1, "a grasper radius in m"));
  if (!o.parse(args)) return 0;
  frames = std::max(2, frames);
  std::printf("| backend | spring | grasped nodes | frame ms (mean) | springs ms/frame w/o builds | compliance builds | "
              "build ms total | frame / explicit |\n|---|---|---|---|---|---|---|---|\n");
  for (const char* backend : {"cpu", "direct"}) {
    // Soft enough that the explicit spring converges, so all three are comparable.
    const sim::Model m = sim::compile(bench_spec(backend, radius, 2.0, frames));
    const Row ex = measure(m, false, true), im = measure(m, true, true), nc = measure(m, true, false);
    for (const auto& [name, r] : {std::pair<const char*, Row>{"explicit", ex}, {"implicit, cached", im},
                                  {"implicit, no cache", nc}})
      std::printf("| %s | %s | %d | %.3f | %.3f | %d | %.1f | %.2f |\n", backend, name, r.grasped, r.frame_ms,
                  r.springs_ms, r.builds, r.build_ms, r.frame_ms / ex.frame_ms);
    std::printf("(%s: %d nodes, %s)\n", backend, m.mesh.num_nodes(), m.solver->name().c_str());
  }
  return 0;
}

}  // namespace softcut::bench
