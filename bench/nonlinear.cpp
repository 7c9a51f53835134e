// softcut bench nonlinear: the cost of a large-deformation frame (DESIGN.md
// §1b, docs/fidelity.md). One box scenario, compiled three ways and stepped
// through the same frames, all measured in this run:
//   corotational  the hybrid (backend direct: the operational factor kept),
//                 its operational region corotational, solved by Newton
//                 with that factor as the PCG preconditioner;
//   linear        the same model with the linear law: today's frame;
//   monolithic    the same mixed model solved on the whole mesh the same
//                 way (backend monolithic: Newton, the whole-mesh factor kept
//                 as the preconditioner): the baseline.
// Ratios: speedup = monolithic / corotational, cost = corotational / linear
// (median frame times). Issue #43 asks for speedup >= 10 and cost <= 5 on
// box_111132 (42 x 21 x 21 cells, a 5,000-tet operational hemisphere).
// Then the paper's two models at their sizes (the knee ligament's 71
// operational tets, the upper leg's 416), corotational against linear:
// issue #43 asks for a corotational frame at >= 1 kHz there.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include "app/options.hpp"
#include "bench/bench.hpp"
#include "bench/bench_models.hpp"
#include "core/atomic_file.hpp"
#include "core/error.hpp"
#include "core/json_text.hpp"
#include "core/threads.hpp"
#include "core/timer.hpp"
#include "mesh/surface.hpp"
#include "sim/cutting.hpp"
#include "sim/model.hpp"
#include "sim/step.hpp"

namespace softcut::bench {

namespace {

using V = Eigen::Vector3d;

// What every series shares: E = 3 kPa, nu = 0.45 with the law `model`, one
// load (its nodes set by the caller) ramped to `force` N at t = 1 s over
// `frames` frames, no outputs.
sim::ScenarioSpec base_spec(int frames, double force, const char* model, backend::Backend b) {
  sim::ScenarioSpec s;
  sim::MaterialAssignment mat;
  mat.name = "tissue";
  mat.young = 3e3;
  mat.poisson = 0.45;
  mat.model = fem::parse_material_model(model);
  s.materials.push_back(mat);
  sim::LoadSpec press;
  press.name = "press";
  press.magnitude = tools::Ramp::linear_ramp(0.0, force, 0.0, 1.0);  // N, to t = 1 s
  s.loads.push_back(press);
  s.timeline.duration = 1.0;
  s.timeline.fps = double(frames);
  s.outputs.csv = false;
  s.solver.backend = b;
  return s;
}

// Box of 2n x n x n cells on 0.1 x 0.05 x 0.05 m (12 n^3 tets), x = 0 fixed,
// operational hemisphere of about `op_tets` tets at the middle of the top
// face; a patch of the top around it pressed down by `force` N at the last
// frame, growing over the frames.
sim::ScenarioSpec box_spec(int n, int op_tets, int frames, double force, const char* model, backend::Backend b) {
  sim::ScenarioSpec s = base_spec(frames, force, model, b);
  s.name = "bench_nonlinear";
  s.mesh.generator = "box";
  s.mesh.options = {{"max.x", 0.1}, {"max.y", 0.05}, {"max.z", 0.05}, {"nx", 2 * n}, {"ny", n}, {"nz", n}};
  // A hemisphere of volume op_tets / (12 n^3) of the box's.
  const double box_volume = 0.1 * 0.05 * 0.05;
  const double r = std::cbrt(3.0 * box_volume * op_tets / (12.0 * n * n * n) / (2.0 * M_PI));
  s.operational.kind = sim::TetSelector::Kind::sphere;
  s.operational.center = V(0.05, 0.025, 0.05);
  s.operational.radius = r;
  s.fixed = sim::NodeSelector::box(V(-1, -1, -1), V(0, 1, 1));
  s.loads[0].nodes = sim::NodeSelector::box(V(0.05 - r / 3, 0.025 - r / 3, 0.05), V(0.05 + r / 3, 0.025 + r / 3, 1));
  s.loads[0].direction = V(0, 0, -1);
  return s;
}

// A paper model (bench_models.hpp: made by the scenario generator of its
// name, with its fixed nodes and operational region): the operational
// surface nodes within `radius` of its centre node pushed in along their
// normals by `force` N in all at the last frame.
sim::ScenarioSpec paper_spec(const std::string& generator, const BenchModel& b, double radius, double force,
                             int frames, const char* model) {
  sim::ScenarioSpec s = base_spec(frames, -force, model, backend::Backend::direct);
  s.name = cat("bench_nonlinear_", generator);
  s.mesh.generator = generator;
  s.operational.kind = sim::TetSelector::Kind::tets;
  for (int t = 0; t < b.mesh.num_tets(); ++t)
    if (b.op_mask[size_t(t)]) s.operational.ids.push_back(t);
  s.fixed = sim::NodeSelector::list(b.fixed);
  const auto on_surface = mesh::surface_node_mask(b.mesh, mesh::extract_surface(b.mesh));
  std::vector<char> operational(size_t(b.mesh.num_nodes()), 0);
  for (int t : s.operational.ids)
    for (int k = 0; k < 4; ++k) operational[size_t(b.mesh.tets(t, k))] = 1;
  std::vector<int> pressed;
  for (int v = 0; v < b.mesh.num_nodes(); ++v)
    if (on_surface[size_t(v)] && operational[size_t(v)] && (b.mesh.node(v) - b.mesh.node(b.center)).norm() <= radius)
      pressed.push_back(v);
  s.loads[0].nodes = sim::NodeSelector::list(pressed);
  s.loads[0].direction_kind = sim::LoadSpec::Direction::normal;  // a negative magnitude pushes in
  return s;
}

struct Series {
  std::string name;
  double compile_ms = 0, median_ms = 0;
  double newton_mean = 0, pcg_mean = 0;  // per frame
  Eigen::MatrixX3d u;                   // the last frame
  std::vector<char> solved;             // (nodes) the frame solved it (the hybrid leaves interior nodes)
  double rotation_max = 0;              // rad, largest rotation of a nonlinear-law tet
  int nodes = 0, tets = 0, operational_tets = 0;
};

Series run(const std::string& name, const sim::ScenarioSpec& spec) {
  Series r;
  r.name = name;
  Timer t;
  const sim::Model m = sim::compile(spec);
  r.compile_ms = t.ms();
  r.nodes = m.mesh.num_nodes(), r.tets = m.mesh.num_tets();
  r.operational_tets = m.partition.counts.operational_tets;
  sim::State s = sim::make_state(m);
  std::vector<double> ms;
  long long cg = 0;
  while (s.frame < m.num_frames - 1) {
    Timer f;
    sim::step(m, s);
    ms.push_back(f.ms());
    cg += s.last_cg_iterations;
    if (m.num_frames <= 100 || s.frame % 100 == 0)  // a long series every 100th frame
      std::fprintf(stderr, "[bench nonlinear]   %s frame %d: %.2f ms, %d Newton steps, %d CG/PCG iterations\n",
                   name.c_str(), s.frame, ms.back(), s.last_newton_iterations, s.last_cg_iterations);
  }
  // Frame 0 is unloaded, and a run's first solve makes its operational
  // factor: the linear series' at frame 0, a Newton series' at frame 1 (its
  // first load). The median is over the steady frames from 2 on.
  ms.erase(ms.begin(), ms.begin() + 2);
  std::sort(ms.begin(), ms.end());
  r.median_ms = ms[ms.size() / 2];
  r.newton_mean = double(s.stats.newton_iterations_total) / std::max(1, s.stats.newton_frames);
  r.pcg_mean = double(cg) / std::max(1, s.stats.frames);
  r.u = s.displacement;
  for (int v = 0; v < m.mesh.num_nodes(); ++v)
    r.solved.push_back(sim::node_set(m, s, v) != hybrid::NodeSet::interior || m.solver->interior_valid());
  r.rotation_max = s.stats.nonlinear_rotation_max;
  return r;
}

}  // namespace

int bench_nonlinear(const Args& args) {
  app::Options o("softcut bench nonlinear",
                 "Times a corotational hybrid frame against the same mixed model solved on the whole mesh by Newton "
                 "with a kept factor (backend monolithic) and against the linear hybrid frame, on a box of 2n x n x n "
                 "cells with an operational hemisphere pressed down (n = 21: box_111132, 5,000 operational tets; "
                 "--quick: n = 8).");
  bool quick = false;
  int n = 21, op_tets = 5000, frames = 6, paper_frames = 1000;
  double force = 0.1;
  std::string json_path;
  o.app().add_flag("--quick", quick, "n = 8, 800 operational tets");
  o.app().add_option("--cells", n, "n (the box has 2n x n x n cells, 12 n^3 tets)")->check(CLI::Range(2, 40));
  o.app().add_option("--op-tets", op_tets, "operational tets (about)")->check(CLI::Range(50, 200000));
  o.app().add_option("--frames", frames, "loaded frames (the load grows over them; the first is not timed)")
      ->check(CLI::Range(3, 100));
  o.app().add_option("--force", force, "the press at the last frame, N (default 0.1: its tets turn by about 30 deg)")
      ->check(CLI::Range(1e-6, 10.0));
  o.app().add_option("--paper-frames", paper_frames,
                     "frames of the paper models' push over its second (1000: frames at 1 kHz, the rate asked for)")
      ->check(CLI::Range(3, 1000));
  o.app().add_option("--json", json_path, "also write the results as JSON")->type_name("FILE");
  if (!o.parse(args)) return 0;
  if (quick) n = 8, op_tets = 800;
  const std::string name = cat("box_", 12 * n * n * n);
  std::fprintf(stderr, "[bench nonlinear] %s, about %d operational tets, %d frames\n", name.c_str(), op_tets, frames);
  const Series corot = run("corotational", box_spec(n, op_tets, frames, force, "corotational", backend::Backend::direct));
  const Series linear = run("linear", box_spec(n, op_tets, frames, force, "linear", backend::Backend::direct));
  const Series mono = run("monolithic", box_spec(n, op_tets, frames, force, "corotational", backend::Backend::monolithic));
  // The same answer: the hybrid's surface and operational nodes against the whole-mesh solve.
  double diff = 0;
  for (int v = 0; v < corot.u.rows(); ++v)
    if (corot.solved[size_t(v)]) diff = std::max(diff, (corot.u.row(v) - mono.u.row(v)).norm());
  diff /= std::max(1e-300, mono.u.rowwise().norm().maxCoeff());
  const double speedup = mono.median_ms / corot.median_ms, cost = corot.median_ms / linear.median_ms;
  std::printf("%s (E = 3 kPa, nu = 0.45, x = 0 fixed), a patch of the operational hemisphere pressed to %g N over "
              "%d frames; median frame ms, Newton steps and CG/PCG iterations per frame\n\n"
              "| series | compile ms | frame ms | Newton | CG/PCG |\n|---|---:|---:|---:|---:|\n",
              name.c_str(), force, frames);
  for (const Series* s : {&corot, &linear, &mono})
    std::printf("| %s | %.0f | %.2f | %.1f | %.1f |\n", s->name.c_str(), s->compile_ms, s->median_ms, s->newton_mean,
                s->pcg_mean);
  std::printf("\nspeedup (monolithic / corotational) %.1f (goal >= 10), cost (corotational / linear) %.2f (goal <= "
              "5), max |u - u_monolithic| / max |u| = %.1e; largest rotation of a corotational tet %.1f deg\n",
              speedup, cost, diff, corot.rotation_max * 180 / M_PI);
  // The paper's models at their sizes: a corotational frame against the
  // linear one (issue #43: >= 1 kHz at paper sizes). By default the push's
  // second takes 1,000 frames: a frame's load step is what a run at 1 kHz
  // takes (at 30 frames a step is 33 times that, and takes a Newton step more).
  struct Paper {
    const char* generator;
    BenchModel (*make)();
    double radius, force;  // m, N: the pressed patch and its push at the last frame
  };
  const Paper papers[] = {{"ligament", ligament, 0.0025, 0.005}, {"upper_leg", upper_leg, 0.005, 0.1}};
  std::printf("\nThe paper's models (Wu & Heng 2005, Table 2) at their sizes: the operational surface nodes near the "
              "region's centre pushed in, over %d frames; median frame ms of the frames from 2 on\n\n"
              "| model | tets | operational tets | corotational frame ms | Hz | Newton | CG/PCG | largest rotation deg "
              "| linear frame ms | cost |\n|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|\n",
              paper_frames);
  Json paper_json = Json::array();
  for (const Paper& p : papers) {
    const BenchModel b = p.make();
    const Series c = run(cat(p.generator, " corotational"),
                         paper_spec(p.generator, b, p.radius, p.force, paper_frames, "corotational"));
    const Series l =
        run(cat(p.generator, " linear"), paper_spec(p.generator, b, p.radius, p.force, paper_frames, "linear"));
    if (c.nodes != b.mesh.num_nodes() || c.tets != b.mesh.num_tets())
      fail("bench nonlinear: the '", p.generator, "' generator made ", c.tets, " tets, the bench's model ",
           b.mesh.num_tets(), ": its operational region would not be the paper's");
    std::printf("| %s | %d | %d | %.3f | %.0f | %.1f | %.1f | %.1f | %.3f | %.2f |\n", p.generator, c.tets,
                c.operational_tets, c.median_ms, 1e3 / c.median_ms, c.newton_mean, c.pcg_mean,
                c.rotation_max * 180 / M_PI, l.median_ms, c.median_ms / l.median_ms);
    paper_json.push_back({{"model", p.generator}, {"tets", c.tets}, {"operational_tets", c.operational_tets},
                          {"force_n", p.force}, {"frame_ms_median", json_number(c.median_ms, 6)},
                          {"frame_hz", json_number(1e3 / c.median_ms, 6)},
                          {"newton_iterations_mean", json_number(c.newton_mean, 6)},
                          {"pcg_iterations_mean", json_number(c.pcg_mean, 6)},
                          {"rotation_max_deg", json_number(c.rotation_max * 180 / M_PI, 6)},
                          {"linear_frame_ms_median", json_number(l.median_ms, 6)},
                          {"cost_vs_linear", json_number(c.median_ms / l.median_ms, 6)}});
  }
  if (!json_path.empty()) {
    Json j = {{"benchmark", "nonlinear"}, {"quick", quick}, {"threads", thread_policy().threads},
              {"model", name}, {"tets", 12 * n * n * n}, {"operational_tets_target", op_tets}, {"frames", frames},
              {"force_n", force}};
    for (const Series* s : {&corot, &linear, &mono})
      j[s->name] = {{"compile_ms", json_number(s->compile_ms, 6)}, {"frame_ms_median", json_number(s->median_ms, 6)},
                    {"newton_iterations_mean", json_number(s->newton_mean, 6)},
                    {"pcg_iterations_mean", json_number(s->pcg_mean, 6)}};
    j["speedup_vs_monolithic"] = json_number(speedup, 6);
    j["cost_vs_linear"] = json_number(cost, 6);
    j["relative_difference_vs_monolithic"] = json_number(diff, 6);
    j["rotation_max_deg"] = json_number(corot.rotation_max * 180 / M_PI, 6);
    j["paper"] = paper_json;
    write_file_atomic(json_path, json_text(j));
  }
  return 0;
}

}  // namespace softcut::bench
