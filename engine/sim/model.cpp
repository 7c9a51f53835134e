#include "sim/model.hpp"

#include <algorithm>
#include <cmath>
#include <map>
#include <optional>

#include "core/timer.hpp"
#include "sim/cutting.hpp"
#include "sim/mesh_source.hpp"
#include "sim/tissue.hpp"

namespace softcut::sim {

namespace {

std::string prefixed(const std::string& where, const std::string& item) {
  return where.empty() ? item : where + ": " + item;
}

SelectContext context(const Model& m) { return SelectContext{m.mesh, m.surface, m.named_sets}; }

// The material of an assignment and its density (kg/m^3).
std::pair<fem::Material, double> resolve_material(const MaterialAssignment& a) {
  const std::string w = prefixed(a.where, "material '" + a.name + "'");
  fem::Material mat{a.young, a.poisson};
  double density = a.density > 0 ? a.density : 1000.0;
  if (!a.preset.empty()) {
    const TissuePreset& p = tissue_preset(a.preset, w);
    if (!(a.young > 0)) mat.young = p.material.young;
    if (!(a.poisson > -1 && a.poisson < 0.5)) mat.poisson = p.material.poisson;
    if (!(a.density > 0)) density = p.density;
  }
  if (a.model) mat.model = *a.model;
  fem::check_material(mat, w);
  return {mat, density};
}

// The motions' nodes, added to `fixed` (sorted, unique); a node in two
// motions is an error naming both.
void resolve_motions(Model& m, const SelectContext& ctx, std::vector<int>& fixed) {
  std::map<int, std::string> owner;
  for (const auto& mo : m.spec.motions) {
    const std::string w = prefixed(mo.where, "motion '" + mo.name + "'");
    Motion r{mo.name, select_nodes(mo.nodes, ctx, w), mo.path};
    if (r.nodes.empty()) fail(w, ": selects no node");
    for (int n : r.nodes)
      if (const auto [it, fresh] = owner.emplace(n, mo.name); !fresh)
        fail(w, ": node ", n, " is moved by motion '", it->second, "' too; a node follows one motion");
    fixed.insert(fixed.end(), r.nodes.begin(), r.nodes.end());
    m.motions.push_back(std::move(r));
  }
  std::sort(fixed.begin(), fixed.end());
  fixed.erase(std::unique(fixed.begin(), fixed.end()), fixed.end());
}

// The hybrid model condenses the nonoperational region once, with its fixed
// nodes at rest: a node it touches may not move.
void check_motions(const Model& m) {
  if (m.motions.empty() || m.spec.solver.backend == backend::Backend::monolithic || m.spec.solver.whole_body) return;
  std::vector<char> condensed(size_t(m.mesh.num_nodes()), 0);
  for (int t : m.partition.nonoperational_tets)
    for (int k = 0; k < 4; ++k) condensed[size_t(m.mesh.tets(t, k))] = 1;
  for (size_t i = 0; i < m.motions.size(); ++i)
    for (int n : m.motions[i].nodes)
      if (condensed[size_t(n)])
        fail(prefixed(m.spec.motions[i].where, "motion '" + m.motions[i].name + "'"), ": node ", n,
             " belongs to the nonoperational (condensed) region, which the hybrid model precomputes with its ",
             "fixed nodes at rest; take the moved nodes into s:operational{}, or solve the whole mesh ",
             "(s:solver{ backend = \"monolithic\" })");
}

}  // namespace

Eigen::MatrixX3d prescribed_displacements(const Model& m, double t, Eigen::Index nnode) {
  if (m.motions.empty()) return {};
  Eigen::MatrixX3d u = Eigen::MatrixX3d::Zero(nnode, 3);
  for (const Motion& mo : m.motions) {
    const Eigen::RowVector3d d = tools::evaluate(mo.path, t).transpose();
    for (int n : mo.nodes) u.row(n) = d;
  }
  return u;
}

bool wants_gpu_context(const ScenarioSpec& spec) {
  return spec.outputs.render.enabled || spec.solver.backend == backend::Backend::gpu;
}

Model compile(const ScenarioSpec& spec, const backend::RunResources& resources) {
  check_spec(spec);
  Model m;
  m.spec = spec;
  Diagnostics diag;
  Timer t;

  LoadedMesh lm = load_mesh_source(spec.mesh, diag);
  m.mesh = std::move(lm.mesh);
  m.named_sets = std::move(lm.named_sets);
  m.surface = mesh::extract_surface(m.mesh);
  m.rest_normals = mesh::vertex_normals(m.mesh, m.surface);
  m.precompute_ms.emplace_back("mesh", t.ms());
  t.reset();

  const SelectContext ctx = context(m);
  m.tet_material.assign(m.mesh.num_tets(), fem::Material{});
  std::vector<double> density(size_t(m.mesh.num_tets()), 1000.0);  // kg/m^3
  m.tet_group.assign(m.mesh.num_tets(), int(spec.materials.size()));
  for (std::size_t i = 0; i < spec.materials.size(); ++i) {
    const MaterialAssignment& a = spec.materials[i];
    const std::string w = prefixed(a.where, "material '" + a.name + "'");
    const auto [mat, rho] = resolve_material(a);
    warn_implausible_material(mat.young, a.density, w, diag);
    const std::vector<int> tets = select_tets(a.tets, ctx, w);
    if (tets.empty()) diag.warn(w, ": selects no tet");
    for (int k : tets) m.tet_material[k] = mat, density[size_t(k)] = rho, m.tet_group[k] = int(i);
  }
  if (spec.gravity.squaredNorm() > 0)  // a dead load on every tet (split tets inherit it)
    for (int k = 0; k < m.mesh.num_tets(); ++k)
      for (int d = 0; d < 3; ++d) m.tet_material[size_t(k)].body_force[size_t(d)] = density[size_t(k)] * spec.gravity(d);
  for (const auto& a : spec.prestress) {  // after the materials: they do not reset it
    const std::string w = prefixed(a.where, "prestress '" + a.name + "'");
    const std::vector<int> tets = select_tets(a.tets, ctx, w);
    if (tets.empty()) diag.warn(w, ": selects no tet");
    const std::array<double, 6> eps0 = voigt_strain(a.strain);
    for (int k : tets) m.tet_material[k].initial_strain = eps0;
  }

  std::vector<char> operational(m.mesh.num_tets(), 0);
  for (int k : select_tets(spec.operational, ctx, "operational")) operational[k] = 1;
  std::vector<int> fixed = select_nodes(spec.fixed, ctx, "fixed");
  if (fixed.empty() && spec.motions.empty())
    fail(prefixed(spec.fixed.where, "fixed"), ": selects no node; the body needs fixed nodes (a ",
         to_string(spec.fixed.kind), " selector matched nothing)");
  resolve_motions(m, ctx, fixed);
  m.partition = hybrid::make_partition(m.mesh, operational, fixed);
  check_motions(m);

  if (spec.outputs.log_all_surface)
    m.log_nodes = m.surface.nodes;
  else
    m.log_nodes = select_nodes(spec.outputs.log_nodes, ctx, "outputs.log_nodes");
  for (size_t i = 0; i < spec.expectations.size(); ++i) {
    const ExpectationSpec& e = spec.expectations[i];
    m.expectation_nodes.push_back(e.bounds ? select_nodes(e.nodes, ctx, cat("expectation '", e.name, "'"))
                                           : std::vector<int>{});
  }
  m.precompute_ms.emplace_back("selectors", t.ms());

  for (const auto& l : spec.loads) resolve_load(m, l);  // errors now rather than at frame 0

  // Interior nonoperational nodes are condensed away; recover them each frame
  // only when an output or an expectation's bounds need them (a script that
  // reads one otherwise gets an error: check_solved).
  bool need_interior = spec.outputs.vtu;
  for (int n : m.log_nodes) need_interior |= m.partition.node_set[n] == hybrid::NodeSet::interior;
  for (const auto& nodes : m.expectation_nodes)
    for (int n : nodes) need_interior |= m.partition.node_set[n] == hybrid::NodeSet::interior;
  m.solver = backend::make_solver(m.mesh, m.tet_material, m.partition, spec.solver, need_interior, resources, diag);
  for (const auto& p : m.solver->precompute_ms()) m.precompute_ms.push_back(p);

  m.dt = 1.0 / spec.timeline.fps;
  m.num_frames = int(std::floor(spec.timeline.duration * spec.timeline.fps + 1e-9)) + 1;
  m.warnings = std::move(diag.warnings);
  return m;
}

ActiveLoad resolve_load(const Model& m, const LoadSpec& spec) {
  const std::string w = prefixed(spec.where, "load '" + spec.name + "'");
  ActiveLoad a;
  a.spec = spec;
  a.nodes = select_nodes(m, spec.nodes, w);
  if (a.nodes.empty()) fail(w, ": selects no node");
  a.directions.resize(Eigen::Index(a.nodes.size()), 3);
  const Eigen::Vector3d dir = spec.direction.normalized();
  for (size_t k = 0; k < a.nodes.size(); ++k) {
    const int n = a.nodes[k];
    const hybrid::NodeSet set = m.partition.node_set[n];
    if (set == hybrid::NodeSet::fixed)
      fail(w, ": node ", n, " is fixed (a load there has no effect); remove it from the load or from fixed");
    if (set == hybrid::NodeSet::interior)
      fail(w, ": node ", n, " is an interior nonoperational node, condensed away by the hybrid model; load surface ",
           "nodes or make that region operational");
    if (spec.direction_kind == LoadSpec::Direction::normal) {
      if (m.rest_normals.row(n).squaredNorm() == 0)
        fail(w, ": direction 'normal' but node ", n, " is not on the surface");
      a.directions.row(Eigen::Index(k)) = m.rest_normals.row(n);
    } else {
      a.directions.row(Eigen::Index(k)) = dir.transpose();
    }
  }
  return a;
}

namespace {

// Rest-surface nodes that scripted loads name or that a tool tip passes
// within three radii of, sampled at every frame time (at most 4096 samples
// per tool): what the run will load, so the solver can prepare their data.
std::vector<int> nodes_to_be_loaded(const Model& m, const State& s) {
  std::vector<char> mark(size_t(m.mesh.num_nodes()), 0);
  for (const auto& l : s.loads)
    for (int v : l.nodes) mark[size_t(v)] = 1;
  const int frames = std::max(1, m.num_frames), stride = std::max(1, frames / 4096);
  for (const auto& t : s.tool_specs) {
    const double reach2 = 9.0 * t.radius * t.radius;
    for (int f = 0; f < frames; f += stride) {
      const Eigen::Vector3d tip = tools::evaluate(t.path, m.frame_time(f));
      for (int v : m.surface.nodes)
        if ((m.mesh.node(v) - tip).squaredNorm() <= reach2) mark[size_t(v)] = 1;
    }
  }
  std::vector<int> out;
  for (size_t v = 0; v < mark.size(); ++v)
    if (mark[v]) out.push_back(int(v));
  return out;
}

}  // namespace

State make_state(const Model& m) {
  State s;
  const int n = m.mesh.num_nodes();
  s.displacement = Eigen::MatrixX3d::Zero(n, 3);
  s.forces = Eigen::MatrixX3d::Zero(n, 3);
  for (const auto& l : m.spec.loads) s.loads.push_back(resolve_load(m, l));
  s.tool_specs = m.spec.tools;
  s.expectations.resize(m.spec.expectations.size());
  s.tools.resize(s.tool_specs.size());
  for (size_t k = 0; k < s.tools.size(); ++k) s.tools[k].tip = tools::evaluate(s.tool_specs[k].path, 0.0);
  if (m.solver) {
    m.solver->start_run(s.solver_run, nullptr);
    m.solver->prefetch(nodes_to_be_loaded(m, s), s.solver_run);
  }
  return s;
}

State copy_state(const Model& m, const State& s) {
  State c;
  static_cast<PhysicsState&>(c) = PhysicsState{s.frame, s.time, s.displacement, s.forces, s.tools,
                                                s.cut ? std::make_unique<CutMesh>(*s.cut) : nullptr};
  c.loads = s.loads;
  c.tool_specs = s.tool_specs;
  c.stop_requested = s.stop_requested;
  c.last = s.last;
  c.last_cg_iterations = s.last_cg_iterations;
  c.last_newton_iterations = s.last_newton_iterations;
  c.last_validity = s.last_validity;
  c.stats = s.stats;
  c.warnings = s.warnings;
  c.cut_events = s.cut_events;
  c.metrics = s.metrics;
  c.springs.enabled = s.springs.enabled;
  if (m.solver) {
    const std::optional<backend::CutBody> body = c.cut ? std::optional(cut_body(*c.cut)) : std::nullopt;
    m.solver->start_run(c.solver_run, body ? &*body : nullptr);
  }
  return c;
}

Eigen::MatrixX3d deformed_positions(const Model& m, const State& s) {
  return current_mesh(m, s).nodes + s.displacement;
}

std::vector<int> select_nodes(const Model& m, const NodeSelector& sel, const std::string& where) {
  return select_nodes(sel, context(m), where);
}

void check_solved(const Model& m, const State&, int n, const std::string& what) {
  if (m.solver->interior_valid() || n < 0 || n >= m.mesh.num_nodes()) return;  // cutting appends operational nodes
  if (m.partition.node_set[size_t(n)] == hybrid::NodeSet::interior)
    fail(what, ": node ", n, " lies inside the nonoperational region, whose displacements the hybrid model "
         "condenses away and recovers only when asked; add it to s:output{ log = ... } to have it solved every frame");
}

Eigen::Vector3d mean_displacement(const State& s, const std::vector<int>& nodes) {
  if (nodes.empty()) fail("mean_displacement: empty node set");
  Eigen::Vector3d sum = Eigen::Vector3d::Zero();
  for (int n : nodes) {
    if (n < 0 || n >= s.displacement.rows())
      fail("mean_displacement: node ", n, " out of range (", s.displacement.rows(), " nodes)");
    sum += s.displacement.row(n).transpose();
  }
  return sum / double(nodes.size());
}

}  // namespace softcut::sim
