#include "sim/mesh_source.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "mesh/generate/box.hpp"
#include "mesh/generate/cylinder.hpp"
#include "mesh/generate/presets.hpp"
#include "mesh/io/mesh_io.hpp"
#include "mesh/mesher/organs.hpp"

namespace softcut::sim {

namespace {

// Takes options by name, remembers what was asked for, and rejects leftovers.
class Options {
 public:
  Options(const std::map<std::string, double>& opts, std::string what) : left_(opts), what_(std::move(what)) {}

  void num(const char* name, double& v) {
    known_.push_back(name);
    if (auto it = left_.find(name); it != left_.end()) {
      if (!std::isfinite(it->second)) fail(what_, ": option '", name, "' must be finite");
      v = it->second;
      left_.erase(it);
    }
  }
  template <class Int>
  void integer(const char* name, Int& v) {
    double d = double(v);
    num(name, d);
    if (d != std::floor(d) || d < 0 || d > 1e9)
      fail(what_, ": option '", name, "' expected an integer from 0 to 1000000000, got ", d);
    v = Int(d);
  }
  void vec(const std::string& name, Eigen::Vector3d& v) {
    static const char* axes[3] = {".x", ".y", ".z"};
    for (int c = 0; c < 3; ++c) {
      known_.push_back(name + axes[c]);
      if (auto it = left_.find(name + axes[c]); it != left_.end()) {
        if (!std::isfinite(it->second)) fail(what_, ": option '", it->first, "' must be finite");
        v(c) = it->second;
        left_.erase(it);
      }
    }
  }
  // An older spelling of option `name`, still read (not listed as known).
  void alias(const char* old_name, const char* name) {
    const auto it = left_.find(old_name);
    if (it == left_.end()) return;
    if (left_.count(name)) fail(what_, ": options '", old_name, "' and '", name, "' are the same option; give '", name, "' only");
    left_[name] = it->second;
    left_.erase(old_name);
  }
  void finish() const {
    if (left_.empty()) return;
    std::string known;
    for (const auto& k : known_) known += (known.empty() ? "" : ", ") + k;
    fail(what_, ": unknown option '", left_.begin()->first, "' (known: ", known, ")");
  }
  const std::vector<std::string>& known() const { return known_; }
  // Whether the options name any of these (asked before they are taken).
  bool asks_for(std::initializer_list<const char*> names) const {
    return std::any_of(names.begin(), names.end(), [&](const char* n) { return left_.count(n) > 0; });
  }

 private:
  std::map<std::string, double> left_;
  std::string what_;
  std::vector<std::string> known_;
};

std::string too_many_tets(double tets, double max_tets, const char* advice) {
  char n[32], limit[32];
  std::snprintf(n, sizeof n, "%.0f", tets);
  std::snprintf(limit, sizeof limit, "%.0f", max_tets);
  return cat(n, " tetrahedra, over this run's limit of ", limit, "; ", advice,
             " (softcut run/check --max-tets N raises the limit, --trust lifts it)");
}

void common(Options& o, int& target_tets, int& target_nodes, double& jitter, unsigned& seed, int& label) {
  o.integer("target_tets", target_tets);
  o.integer("target_nodes", target_nodes);
  o.num("jitter", jitter);
  o.integer("seed", seed);
  o.integer("label", label);
}

// A preset's resolution (its target counts) yields to the one asked for:
// cell counts or targets given replace both of its targets.
void band_options(Options& o, mesh::BandOptions& b) {
  if (o.asks_for({"along", "across", "through", "target_tets", "target_nodes"})) b.target_tets = b.target_nodes = 0;
  o.vec("base_center", b.base_center);
  o.num("length", b.length), o.num("width", b.width), o.num("thickness", b.thickness);
  // `twist` (degrees), as `softcut mesh generate band --twist`; twist_deg is its old name.
  o.alias("twist_deg", "twist");
  o.num("flare", b.flare), o.num("twist", b.twist_deg);
  o.integer("along", b.along), o.integer("across", b.across), o.integer("through", b.through);
  common(o, b.target_tets, b.target_nodes, b.jitter, b.seed, b.label);
}

void tube_options(Options& o, mesh::TubeOptions& t) {
  if (o.asks_for({"radial", "around", "layers", "target_tets", "target_nodes"})) t.target_tets = t.target_nodes = 0;
  o.vec("base_center", t.base_center);
  o.num("inner_radius", t.inner_radius), o.num("outer_radius", t.outer_radius), o.num("length", t.length);
  o.integer("radial", t.radial), o.integer("around", t.around), o.integer("layers", t.layers);
  common(o, t.target_tets, t.target_nodes, t.jitter, t.seed, t.label);
}

// Runs the generator (or only collects option names when `run` is false).
LoadedMesh generate(const std::string& gen, const std::map<std::string, double>& opts, const std::string& what,
                    bool run, std::vector<std::string>* names, double max_tets = kNoTetLimit) {
  Options o(opts, what);
  LoadedMesh out;
  // Refuses the resolution before anything is allocated.
  const auto check_fits = [&](const mesh::MeshSize& size) {
    if (size.tets > max_tets) fail(what, ": this resolution gives ", too_many_tets(size.tets, max_tets, "use a coarser one"));
  };
  out.description = "generator " + gen;
  if (gen == "box") {
    mesh::BoxOptions b;
    o.vec("min", b.min_corner), o.vec("max", b.max_corner);
    o.integer("nx", b.nx), o.integer("ny", b.ny), o.integer("nz", b.nz);
    o.num("jitter", b.jitter), o.integer("seed", b.seed), o.integer("label", b.label);
    o.finish();
    if (run) {
      check_fits(mesh::box_size(b));
      out.mesh = mesh::generate_box(b);
      out.description = cat("generator box (", b.nx, " x ", b.ny, " x ", b.nz, " cells)");
    }
  } else if (gen == "cylinder") {
    mesh::CylinderOptions c;
    o.vec("base_center", c.base_center);
    o.num("radius", c.radius), o.num("length", c.length);
    o.integer("rings", c.rings), o.integer("layers", c.layers);
    common(o, c.target_tets, c.target_nodes, c.jitter, c.seed, c.label);
    o.finish();
    if (run) {
      const auto r = mesh::resolve_cylinder(c);
      check_fits(mesh::cylinder_size(r.rings, r.layers));
      out.mesh = mesh::generate_cylinder(r);
      out.description = cat("generator cylinder (", r.rings, " rings x ", r.layers, " layers)");
    }
  } else if (gen == "tube" || gen == "upper_leg") {
    mesh::TubeOptions t = gen == "tube" ? mesh::TubeOptions{} : mesh::upper_leg_preset();
    tube_options(o, t);
    o.finish();
    if (run) {
      t = mesh::resolve_tube(t);
      check_fits(mesh::tube_size(t.radial, t.around, t.layers));
      out.mesh = mesh::generate_tube(t);
      out.named_sets["hole"] = mesh::tube_hole_nodes(out.mesh, t);
      out.description = cat("generator ", gen, " (", t.radial, " radial x ", t.around, " around x ", t.layers,
                            " layers; hole of radius ", t.inner_radius, " m)");
    }
  } else if (gen == "band" || gen == "ligament") {
    mesh::BandOptions b = gen == "band" ? mesh::BandOptions{} : mesh::ligament_preset();
    band_options(o, b);
    o.finish();
    if (run) {
      const auto r = mesh::resolve_band(b);
      check_fits(mesh::band_size(r.along, r.across, r.through));
      out.mesh = mesh::generate_band(r);
      out.description = cat("generator ", gen, " (", r.along, " along x ", r.across, " across x ", r.through, " through)");
    }
  } else if (std::find(mesh::organ_kinds().begin(), mesh::organ_kinds().end(), gen) != mesh::organ_kinds().end()) {
    mesh::OrganOptions g;
    if (opts.count("cell_size") && !opts.count("target_tets")) g.target_tets = 0;  // a cell size alone sizes the mesh
    o.integer("target_tets", g.target_tets), o.num("cell_size", g.cell_size), o.num("scale", g.scale);
    o.vec("fine_center", g.fine_center), o.num("fine_radius", g.fine_radius), o.num("fine_ratio", g.fine_ratio);
    if (gen == "liver") o.num("lesion_radius", g.lesion_radius), o.vec("lesion_center", g.lesion_center);
    o.num("sliver_bound", g.sliver_bound_deg), o.integer("seed", g.seed);
    o.finish();
    if (run) {
      mesh::MesherReport r;
      try {
        out.mesh = mesh::generate_organ(gen, g, max_tets, &r);
      } catch (const Error& e) {
        fail(what, ": ", e.what());  // where the scenario asked for it
      }
      out.description = cat("generator ", gen, " (CGAL Mesh_3: ", r.tets, " tets, min dihedral ", std::round(r.min_dihedral_deg * 10) / 10, " deg)");
    }
  } else {
    fail(what, ": unknown generator '", gen,
         "' (use box, cylinder, tube, band, ligament, upper_leg, liver, kidney or knee_ligament)");
  }
  if (names) *names = o.known();
  return out;
}

}  // namespace

std::vector<std::string> generator_options(const std::string& generator) {
  std::vector<std::string> names;
  generate(generator, {}, "mesh", false, &names);
  return names;
}

LoadedMesh load_mesh_source(const MeshSource& src, Diagnostics& diag, double max_tets, const mesh::ReadOptions& read) {
  const std::string what = src.where.empty() ? std::string("mesh") : src.where + ": mesh";
  const int given = src.given.num_tets() > 0;
  const int sources = given + !src.file.empty() + !src.generator.empty();
  if (sources != 1)
    fail(what, ": give exactly one of a mesh file, a generator, or a mesh (got ", sources, ")");
  LoadedMesh out;
  if (src.preloaded) {
    out.mesh = *src.preloaded;
    out.named_sets = src.preloaded_sets;
    diag.warnings.insert(diag.warnings.end(), src.preloaded_warnings.begin(), src.preloaded_warnings.end());
    out.description = !src.file.empty() ? "file " + src.file.string() : "generator " + src.generator;
  } else if (given) {
    out.mesh = src.given;
    out.named_sets = src.named_sets;
    out.description = "given mesh";
    mesh::validate(out.mesh, what, diag);
  } else if (!src.file.empty()) {
    if (!src.options.empty()) fail(what, ": generator options given with a mesh file ", src.file.string());
    out.mesh = mesh::read_mesh(src.file, diag, read);
    if (out.mesh.num_tets() > max_tets)
      fail(what, ": ", src.file.string(), " has ", too_many_tets(out.mesh.num_tets(), max_tets, "use a coarser mesh"));
    out.named_sets = src.named_sets;
    out.description = "file " + src.file.string();
  } else {
    out = generate(src.generator, src.options, what + " generator '" + src.generator + "'", true, nullptr, max_tets);
    mesh::validate(out.mesh, out.description, diag);
  }
  for (const auto& [name, ids] : out.named_sets)
    for (int n : ids)
      if (n < 0 || n >= out.mesh.num_nodes())
        fail(what, ": node set '", name, "' has node ", n, " outside the mesh (", out.mesh.num_nodes(), " nodes)");
  return out;
}

}  // namespace softcut::sim
