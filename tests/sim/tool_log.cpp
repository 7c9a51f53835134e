#include "sim/tool_log.hpp"

#include <doctest/doctest.h>

#include <fstream>
#include <sstream>

#include "fem/assembly.hpp"
#include "fem/dof_map.hpp"
#include "fixtures.hpp"
#include "sim/cutting.hpp"
#include "sim/outputs.hpp"
#include "sim/step.hpp"
#include "test_support.hpp"

namespace fs = std::filesystem;
namespace sim = softcut::sim;
namespace tools = softcut::tools;
using V = Eigen::Vector3d;

namespace {

// A 10 x 2 x 2 cm box held at x = 0, no scripted load: only the tools load it.
// Every node is logged, so the hybrid backends solve the interior too and
// K u can be formed from the displacements.
sim::ScenarioSpec tool_box(const fs::path& dir, softcut::backend::Backend backend) {
  auto spec = softcut::test::cantilever_spec(dir, 0.3);
  spec.mesh.options["nx"] = 10, spec.mesh.options["ny"] = 4, spec.mesh.options["nz"] = 4;  // 1 x 0.5 x 0.5 cm cells
  spec.loads.clear();
  spec.outputs.log_all_surface = false;
  spec.outputs.log_nodes.kind = sim::NodeSelector::Kind::all;
  spec.solver.backend = backend;
  return spec;
}

tools::ToolSpec probe(double force) {
  tools::ToolSpec p;
  p.name = "probe, blunt";  // a comma: the CSV quotes it
  p.kind = tools::ToolSpec::Kind::probe;
  p.radius = 0.005;
  p.force = tools::Ramp::constant_value(force);
  p.path = tools::Path::polyline({0.0, 0.3}, {V(0.03, 0.01, 0.0235), V(0.03, 0.01, 0.0225)});
  return p;
}

tools::ToolSpec pressing_blade() {
  auto b = softcut::test::cutting_blade(V(0, 1, 0), V(0, 0, -1));
  b.blade_length = 0.01;
  b.cut_pressure = 1e12;  // presses, never cuts
  b.path = tools::Path::polyline({0.0, 0.3}, {V(0.05, 0.01, 0.0205), V(0.05, 0.01, 0.0201)});
  return b;
}

struct Row {
  int frame = 0;
  std::string tool, kind;
  int engaged = 0, nodes = 0, cut = 0;
  V force = V::Zero();
  double pressure = 0;
};

// tools.csv, parsed as a CSV reader would (quoted fields included).
std::vector<Row> read_tools_csv(const fs::path& file) {
  std::ifstream in(file);
  std::string line;
  std::getline(in, line);
  REQUIRE(line == "frame,time,tool,kind,engaged,nodes,fx,fy,fz,pressure,cut");
  std::vector<Row> rows;
  while (std::getline(in, line)) {
    std::vector<std::string> cells;
    std::string cell;
    bool quoted = false;
    for (std::size_t i = 0; i < line.size(); ++i) {
      const char c = line[i];
      if (quoted && c == '"' && i + 1 < line.size() && line[i + 1] == '"') cell += '"', ++i;
      else if (c == '"') quoted = !quoted;
      else if (c == ',' && !quoted) cells.push_back(cell), cell.clear();
      else cell += c;
    }
    cells.push_back(cell);
    REQUIRE(cells.size() == 11);
    Row r;
    r.frame = std::stoi(cells[0]);
    r.tool = cells[2], r.kind = cells[3];
    r.engaged = std::stoi(cells[4]), r.nodes = std::stoi(cells[5]);
    r.force = V(std::stod(cells[6]), std::stod(cells[7]), std::stod(cells[8]));
    r.pressure = std::stod(cells[9]);
    r.cut = std::stoi(cells[10]);
    rows.push_back(r);
  }
  return rows;
}

// Reactions r = K u - f0 of the whole (rest) mesh, K assembled by the
// triplet reference assembler (not the solver's), per node (nnode x 3), N.
Eigen::MatrixX3d reactions(const sim::Model& m, const sim::State& s) {
  const auto K = softcut::fem::assemble_stiffness_triplets(m.mesh, m.tet_material);
  Eigen::MatrixX3d r = softcut::fem::unflatten(K * softcut::fem::flatten(s.displacement));
  return r - softcut::fem::element_loads(m.mesh, m.tet_material);
}

// Runs the spec frame by frame; after each frame checks every tool's
// tools.csv force against the reactions at its nodes and the fixed nodes'.
void check_against_reactions(sim::ScenarioSpec spec, const fs::path& dir) {
  const sim::Model m = sim::compile(spec);
  sim::State s = sim::make_state(m);
  sim::Recorder rec(m, dir);
  std::vector<Eigen::MatrixX3d> reaction;
  std::vector<std::vector<std::vector<int>>> nodes;  // [frame][tool]
  while (s.frame < m.num_frames - 1) {
    sim::step(m, s);
    rec.record(m, s);
    reaction.push_back(reactions(m, s));
    nodes.emplace_back();
    for (const auto& ts : s.tools) nodes.back().push_back(ts.nodes);
  }
  rec.finish(m, s, sim::RunResult{});
  const std::vector<Row> rows = read_tools_csv(dir / "tools.csv");
  REQUIRE(rows.size() == m.spec.tools.size() * std::size_t(m.num_frames));
  int engaged = 0;
  double largest = 0;
  for (const Row& r : rows) {
    const std::size_t k = std::size_t(&r - rows.data()) % m.spec.tools.size();
    CAPTURE(r.frame);
    CAPTURE(r.tool);
    CHECK(r.tool == m.spec.tools[k].name);
    CHECK(r.kind == tools::to_string(m.spec.tools[k].kind));
    const Eigen::MatrixX3d& R = reaction[std::size_t(r.frame)];
    const std::vector<int>& tool_nodes = nodes[std::size_t(r.frame)][k];
    CHECK(r.nodes == int(tool_nodes.size()));
    // The premise: no other tool acts on these nodes.
    for (std::size_t o = 0; o < m.spec.tools.size(); ++o)
      for (int n : nodes[std::size_t(r.frame)][o])
        REQUIRE((o == k || std::find(tool_nodes.begin(), tool_nodes.end(), n) == tool_nodes.end()));
    // The tool's nodes carry only its load: their reactions sum to its force
    // (shares on fixed nodes go into the support and are not counted).
    V at_tool = V::Zero();
    std::vector<char> fixed(std::size_t(m.mesh.num_nodes()), 0);
    for (int f : m.partition.fixed) fixed[std::size_t(f)] = 1;
    for (int n : tool_nodes)
      if (!fixed[std::size_t(n)]) at_tool += R.row(n).transpose();
    V at_fixed = V::Zero();
    for (int f : m.partition.fixed) at_fixed += R.row(f).transpose();
    const double scale = std::max(r.force.norm(), 1e-9);
    if (m.spec.tools.size() == 1) {
      // One tool on a body held only by its fixed nodes: they hold all of it.
      CHECK((at_fixed + r.force).norm() <= 1e-6 * scale);
    }
    CHECK((at_tool - r.force).norm() <= 1e-6 * scale);
    engaged += r.engaged;
    largest = std::max(largest, r.force.norm());
  }
  CHECK(engaged > 0);
  CHECK(largest > 1e-3);  // real loads were compared, not 0 = 0
}

}  // namespace

TEST_SUITE("sim/tool_log") {
  TEST_CASE("a grasper's force in tools.csv is the sum of the reactions K u at its nodes and of the fixed nodes'") {
    for (const auto backend : {softcut::backend::Backend::direct, softcut::backend::Backend::monolithic}) {
      CAPTURE(softcut::backend::to_string(backend));
      const fs::path dir = softcut::test::scratch_dir("tool_log_grasper");
      auto spec = tool_box(dir, backend);
      spec.tools.push_back(softcut::test::spring_grasper(
          300, 0.006, tools::Path::polyline({0.0, 0.3}, {V(0.08, 0.01, 0.021), V(0.08, 0.012, 0.028)})));
      check_against_reactions(spec, dir);
    }
  }

  TEST_CASE("a probe, a pressing scalpel and a grasper at once: each tool's force is the reactions at its nodes") {
    const fs::path dir = softcut::test::scratch_dir("tool_log_three");
    auto spec = tool_box(dir, softcut::backend::Backend::direct);
    spec.tools.push_back(probe(0.02));
    spec.tools.push_back(pressing_blade());
    spec.tools.push_back(softcut::test::spring_grasper(
        300, 0.006, tools::Path::polyline({0.0, 0.3}, {V(0.08, 0.01, 0.021), V(0.08, 0.01, 0.027)})));
    check_against_reactions(spec, dir);
    // The scalpel's row carries its contact pressure.
    const std::vector<Row> rows = read_tools_csv(dir / "tools.csv");
    double pressure = 0;
    for (const Row& r : rows)
      if (r.kind == "scalpel") {
        pressure = std::max(pressure, r.pressure);
        CHECK(r.cut == 0);
      }
    CHECK(pressure > 0);
  }

  TEST_CASE("a probe pressing where the body is held: its shares on fixed nodes go into the support, not into tools.csv") {
    const fs::path dir = softcut::test::scratch_dir("tool_log_fixed");
    auto spec = tool_box(dir, softcut::backend::Backend::direct);
    auto p = probe(0.02);
    p.radius = 0.008;
    p.path = tools::Path::polyline({0.0, 0.3}, {V(0.003, 0.01, 0.0265), V(0.003, 0.01, 0.0255)});
    spec.tools.push_back(p);
    check_against_reactions(spec, dir);
    // The premise: some of its nodes are fixed, so its own total differs.
    const sim::Model m = sim::compile(spec);
    sim::State s = sim::make_state(m);
    sim::step(m, s);
    int fixed = 0;
    for (int n : s.tools[0].nodes) fixed += sim::is_fixed_node(m, s, n);
    CHECK(fixed > 0);
    CHECK((sim::applied_tool_force(m, s, 0) - s.tools[0].total_force).norm() > 1e-4);
  }

  TEST_CASE("summary.json tools: peak and mean force over engaged frames, as tools.csv says") {
    const fs::path dir = softcut::test::scratch_dir("tool_log_summary");
    auto spec = tool_box(dir, softcut::backend::Backend::direct);
    spec.tools.push_back(probe(0.02));
    spec.tools.push_back(pressing_blade());
    const sim::Model m = sim::compile(spec);
    sim::State s = sim::make_state(m);
    sim::Recorder rec(m, dir);
    const sim::RunResult r = sim::run(m, s, rec, {});
    REQUIRE(r.frames == m.num_frames);
    const auto summary = softcut::test::read_json(dir / "summary.json");
    CHECK(summary["outputs"]["tools_csv"] == "tools.csv");
    const auto& list = summary["tools"];
    REQUIRE(list.size() == 2);
    const std::vector<Row> rows = read_tools_csv(dir / "tools.csv");
    for (std::size_t k = 0; k < 2; ++k) {
      double peak = 0, sum = 0, peak_p = 0;
      int n = 0;
      for (std::size_t i = k; i < rows.size(); i += 2) {
        peak_p = std::max(peak_p, rows[i].pressure);
        if (!rows[i].engaged) continue;
        ++n, sum += rows[i].force.norm(), peak = std::max(peak, rows[i].force.norm());
      }
      CAPTURE(k);
      CHECK(list[k]["name"] == m.spec.tools[k].name);
      CHECK(list[k]["frames_engaged"] == n);
      CHECK(n > 0);
      CHECK(list[k]["peak_force_n"].get<double>() == doctest::Approx(peak).epsilon(1e-8));
      CHECK(list[k]["mean_force_n"].get<double>() == doctest::Approx(sum / n).epsilon(1e-8));
      if (k == 1) CHECK(list[k]["peak_pressure_pa"].get<double>() == doctest::Approx(peak_p).epsilon(1e-8));
    }
  }

  TEST_CASE("no tools: no tools.csv, and an earlier run's is removed") {
    const fs::path dir = softcut::test::scratch_dir("tool_log_none");
    std::ofstream(dir / "tools.csv") << "an earlier run's\n";
    auto spec = softcut::test::cantilever_spec(dir, 0.1);
    const sim::Model m = sim::compile(spec);
    sim::State s = sim::make_state(m);
    sim::Recorder rec(m, dir);
    sim::run(m, s, rec, {});
    CHECK_FALSE(fs::exists(dir / "tools.csv"));
    CHECK(softcut::test::read_json(dir / "summary.json")["tools"].empty());
  }
}
