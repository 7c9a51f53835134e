#include "sim/mesh_source.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "mesh/generate/box.hpp"
#include "mesh/generate/cylinder.hpp"
#include "mesh/generate/presets.hpp"
#include "mesh/io/mesh_io.hpp"
#include "core/warning.hpp"
#include "mesh/io/surface_io.hpp"
#include "mesh/mesher/mesh_surface.hpp"
#include "mesh/mesher/organs.hpp"
#include "mesh/units.hpp"

namespace softcut::sim {

namespace {

// Takes options by name, remembers what was asked for, and rejects leftovers.
class Options {
 public:
  Options(const std::map<std::string, double>& opts, std::string what) : left_(opts), what_(std::move(what)) {}

  void num(const char* name, double& v) {
    known_.push_back(name);
    defaults_[name] = v;
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
      defaults_[name + axes[c]] = v(c);
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
  const std::map<std::string, double>& defaults() const { return defaults_; }
  // Whether the options name any of these (asked before they are taken).
  bool asks_for(std::initializer_list<const char*> names) const {
    return std::any_of(names.begin(), names.end(), [&](const char* n) { return left_.count(n) > 0; });
  }

 private:
  std::map<std::string, double> left_;
  std::string what_;
  std::vector<std::string> known_;
  std::map<std::string, double> defaults_;  // the value each option has when not given
};

const char* kRunRaise = "softcut run/check --max-tets N raises the limit, --trust lifts it";

std::string too_many_tets(double tets, double max_tets, const char* advice, const std::string& raise) {
  char n[32], limit[32];
  std::snprintf(n, sizeof n, tets < 1e15 ? "%.0f" : "%.3g", tets);
  std::snprintf(limit, sizeof limit, "%.0f", max_tets);
  return cat(n, " tetrahedra, over this run's limit of ", limit, "; ", advice, " (", raise.empty() ? kRunRaise : raise, ")");
}

// The organ kinds' sizing options (mesh/mesher/organs.hpp), for organs and surfaces.
void sizing_options(Options& o, const std::map<std::string, double>& opts, mesh::OrganOptions& g) {
  if (opts.count("cell_size") && !opts.count("target_tets")) g.target_tets = 0;  // a cell size alone sizes the mesh
  o.integer("target_tets", g.target_tets), o.num("cell_size", g.cell_size), o.num("scale", g.scale);
  o.vec("fine_center", g.fine_center), o.num("fine_radius", g.fine_radius), o.num("fine_ratio", g.fine_ratio);
}

// generator "surface": reads the surfaces (through the checked open, as
// `read` allows), in their unit, and meshes them.
mesh::TetMesh surface_mesh(const MeshSource& src, const mesh::OrganOptions& g, const std::string& what, Diagnostics& diag,
                           const mesh::MeshLimit& limit, const mesh::ReadOptions& read, mesh::MesherReport& r) {
  if (src.surfaces.empty())
    fail(what, ": give the surface file(s) to mesh: options = { file = \"organ.stl\" } or file = { \"organ.stl\", "
         "\"lesion.stl\" } (softcut mesh generate surface IN.stl [IN2 ...] OUT)");
  if (!(g.scale > 0 && g.scale <= 1e6)) fail(what, ": scale must be in (0, 1000000], got ", g.scale);
  std::vector<mesh::SurfaceSoup> soups;
  Eigen::AlignedBox3d box;
  for (const auto& f : src.surfaces) {
    soups.push_back(mesh::read_surface(f, diag, read));
    for (Eigen::Index i = 0; i < soups.back().points.rows(); ++i) box.extend(Eigen::Vector3d(soups.back().points.row(i)));
  }
  std::string unit = src.unit;
  if (unit.empty()) {
    unit = mesh::guess_unit(box.sizes().maxCoeff(), what);
    warn_coded(diag, "unit_guessed", what, ": the surfaces carry no unit; taken as ", unit, " from their size (",
               box.sizes().maxCoeff(), " units across); give the unit to choose (unit = \"mm\", --unit mm)");
  }
  const mesh::SurfaceDomain domain = mesh::surface_domain(soups, mesh::unit_metres(unit, what) * g.scale, diag);
  return mesh::generate_surface(domain, g, limit, &r);
}

void common(Options& o, int& target_tets, int& target_nodes, double& jitter, unsigned& seed, int& label) {
  o.integer("target_tets", target_tets);
  o.integer("target_nodes", target_nodes);
  o.num("jitter", jitter);
  o.integer("seed", seed);
  o.integer("label", label);
}

// The extruded generators (tube and band, and their presets upper_leg and
// ligament) take their options alike, in this order: base_center, the
// dimensions (m, or as named), the cell counts, then the common ones. A
// preset's resolution (its target counts) yields to the one asked for: cell
// counts or targets given replace both of its targets.
template <class O>
void extruded_options(Options& o, O& x, std::initializer_list<std::pair<const char*, double O::*>> dims,
                      std::initializer_list<std::pair<const char*, int O::*>> cells) {
  bool resolution = o.asks_for({"target_tets", "target_nodes"});
  for (const auto& c : cells) resolution = resolution || o.asks_for({c.first});
  if (resolution) x.target_tets = x.target_nodes = 0;
  o.vec("base_center", x.base_center);
  for (const auto& [name, member] : dims) o.num(name, x.*member);
  for (const auto& [name, member] : cells) o.integer(name, x.*member);
  common(o, x.target_tets, x.target_nodes, x.jitter, x.seed, x.label);
}

void band_options(Options& o, mesh::BandOptions& b) {
  using B = mesh::BandOptions;
  // `twist` (degrees), as `softcut mesh generate band --twist`; twist_deg is its old name.
  o.alias("twist_deg", "twist");
  extruded_options<B>(o, b, {{"length", &B::length}, {"width", &B::width}, {"thickness", &B::thickness},
                             {"flare", &B::flare}, {"twist", &B::twist_deg}},
                      {{"along", &B::along}, {"across", &B::across}, {"through", &B::through}});
}

void tube_options(Options& o, mesh::TubeOptions& t) {
  using T = mesh::TubeOptions;
  extruded_options<T>(o, t, {{"inner_radius", &T::inner_radius}, {"outer_radius", &T::outer_radius}, {"length", &T::length}},
                      {{"radial", &T::radial}, {"around", &T::around}, {"layers", &T::layers}});
}

// Runs the generator (or only collects option names when `run` is false).
LoadedMesh generate(const std::string& gen, const std::map<std::string, double>& opts, const std::string& what,
                    bool run, std::vector<std::string>* names, std::map<std::string, double>* defaults = nullptr,
                    double max_tets = kNoTetLimit,
                    const MeshSource* src = nullptr, Diagnostics* diag = nullptr, const mesh::ReadOptions& read = {}) {
  Options o(opts, what);
  mesh::MeshLimit limit;
  limit.max_tets = max_tets;
  if (src && !src->raise_limit.empty()) limit.raise = src->raise_limit;
  if (src) limit.stop = src->stop;
  LoadedMesh out;
  // Refuses the resolution before anything is allocated.
  const auto check_fits = [&](const mesh::MeshSize& size) {
    if (size.tets > max_tets)
      fail(what, ": this resolution gives ", too_many_tets(size.tets, max_tets, "use a coarser one", src ? src->raise_limit : ""));
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
      const auto r = mesh::resolve_cylinder(c, false);
      check_fits(mesh::cylinder_size(r.rings, r.layers));
      mesh::check_target_met("cylinder", mesh::cylinder_size(r.rings, r.layers), c.target_nodes, c.target_tets, "rings, layers");
      out.mesh = mesh::generate_cylinder(r);
      out.description = cat("generator cylinder (", r.rings, " rings x ", r.layers, " layers)");
    }
  } else if (gen == "tube" || gen == "upper_leg") {
    mesh::TubeOptions t = gen == "tube" ? mesh::TubeOptions{} : mesh::upper_leg_preset();
    tube_options(o, t);
    o.finish();
    if (run) {
      t = mesh::resolve_tube(t, false);
      check_fits(mesh::tube_size(t.radial, t.around, t.layers));
      mesh::check_target_met("tube", mesh::tube_size(t.radial, t.around, t.layers), t.target_nodes, t.target_tets,
                             "radial, around, layers");
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
      const auto r = mesh::resolve_band(b, false);
      check_fits(mesh::band_size(r.along, r.across, r.through));
      mesh::check_target_met("band", mesh::band_size(r.along, r.across, r.through), b.target_nodes, b.target_tets,
                             "along, across, through");
      out.mesh = mesh::generate_band(r);
      out.description = cat("generator ", gen, " (", r.along, " along x ", r.across, " across x ", r.through, " through)");
    }
  } else if (std::find(mesh::organ_kinds().begin(), mesh::organ_kinds().end(), gen) != mesh::organ_kinds().end()) {
    mesh::OrganOptions g;
    sizing_options(o, opts, g);
    if (gen == "liver") o.num("lesion_radius", g.lesion_radius), o.vec("lesion_center", g.lesion_center);
    o.num("sliver_bound", g.sliver_bound_deg), o.integer("seed", g.seed);
    o.finish();
    if (run) {
      mesh::MesherReport r;
      try {
        out.mesh = mesh::generate_organ(gen, g, limit, &r);
      } catch (const TimeoutError&) {
        throw;
      } catch (const Error& e) {
        fail(what, ": ", e.what());  // where the scenario asked for it
      }
      out.named_sets = mesh::organ_landmarks(gen, out.mesh, g);  // hilum, lobes, insertions, ...
      out.description = cat("generator ", gen, " (CGAL Mesh_3: ", r.tets, " tets, min dihedral ", std::round(r.min_dihedral_deg * 10) / 10, " deg)");
    }
  } else if (gen == "surface") {
    mesh::OrganOptions g;
    sizing_options(o, opts, g);
    o.num("sliver_bound", g.sliver_bound_deg), o.integer("seed", g.seed);
    o.finish();
    if (run) {
      mesh::MesherReport r;
      Diagnostics none;
      try {
        out.mesh = surface_mesh(*src, g, what, diag ? *diag : none, limit, read, r);
      } catch (const TimeoutError&) {
        throw;
      } catch (const Error& e) {
        const std::string m = e.what();
        if (m.rfind(what, 0) == 0) throw;
        fail(what, ": ", m);  // where the scenario asked for it
      }
      out.description = cat("generator surface (", src->surfaces.size(), " file", src->surfaces.size() == 1 ? "" : "s",
                            ", CGAL Mesh_3: ", r.tets, " tets, min dihedral ", std::round(r.min_dihedral_deg * 10) / 10, " deg)");
    }
  } else {
    fail(what, ": unknown generator '", gen,
         "' (use box, cylinder, tube, band, ligament, upper_leg, liver, kidney, knee_ligament or surface)");
  }
  if (names) *names = o.known();
  if (defaults) *defaults = o.defaults();
  return out;
}

}  // namespace

std::vector<std::string> generator_options(const std::string& generator) {
  std::vector<std::string> names;
  generate(generator, {}, "mesh", false, &names);
  return names;
}

std::map<std::string, double> generator_defaults(const std::string& generator) {
  std::map<std::string, double> values;
  generate(generator, {}, "mesh", false, nullptr, &values);
  return values;
}

std::string generator_option_help(const std::string& name) {
  static const std::map<std::string, std::string> help = {
      {"min", "lower corner, m"},
      {"max", "upper corner, m"},
      {"nx", "cells along x"},
      {"ny", "cells along y"},
      {"nz", "cells along z"},
      {"base_center", "centre of the bottom face, m (the body's axis is +z)"},
      {"radius", "radius, m"},
      {"length", "length along the axis, m"},
      {"rings", "rings of cells from the axis out"},
      {"layers", "layers of cells along the axis"},
      {"inner_radius", "radius of the hole, m"},
      {"outer_radius", "outer radius, m"},
      {"radial", "cells across the wall"},
      {"around", "cells around the axis (>= 3)"},
      {"width", "width at mid-length, m"},
      {"thickness", "thickness, m"},
      {"flare", "width at the ends / width at mid-length"},
      {"twist_deg", "twist from end to end, degrees"},
      {"along", "cells along the length"},
      {"across", "cells across the width"},
      {"through", "cells through the thickness"},
      {"target_tets", "pick the resolution to make about this many tetrahedra (0: none)"},
      {"target_nodes", "pick the resolution to make about this many nodes (0: none)"},
      {"jitter", "move interior nodes by up to this fraction of a cell, in [0, 0.25)"},
      {"seed", "random numbers' seed: same seed, same mesh"},
      {"label", "label of every tet"},
      {"cell_size", "local size h, m: tet circumradius and surface triangle size (sizes the mesh without target_tets)"},
      {"scale", "every length times this"},
      {"fine_center", "grading: centre of the fine region, m"},
      {"fine_radius", "grading: radius of the fine region, m (0: no grading)"},
      {"fine_ratio", "grading: cells this many times the coarse size there, in (0.05, 1]"},
      {"lesion_radius", "radius of the lesion (label 2), m; 0: none"},
      {"lesion_center", "centre of the lesion, m (inside the liver)"},
      {"sliver_bound", "degrees: perturbation and exudation lift every dihedral angle above it"},
  };
  const auto it = help.find(name);
  return it == help.end() ? std::string() : it->second;
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
      fail(what, ": ", src.file.string(), " has ",
           too_many_tets(out.mesh.num_tets(), max_tets, "use a coarser mesh", src.raise_limit));
    mesh::scale_nodes(out.mesh, (src.unit.empty() ? 1.0 : mesh::unit_metres(src.unit, what)) * src.scale,
                      what + ": scale");
    out.named_sets = src.named_sets;
    out.description = "file " + src.file.string();
  } else {
    if (src.scale != 1 || (!src.unit.empty() && src.generator != "surface"))
      fail(what, ": unit and scale apply to a mesh file; a generator's lengths are metres (scale its options, "
           "or give the organ kinds and surfaces options.scale)");
    out = generate(src.generator, src.options, what + " generator '" + src.generator + "'", true, nullptr, nullptr,
                   max_tets, &src, &diag, read);
    mesh::validate(out.mesh, out.description, diag);
  }
  if (!given && !src.preloaded)
    mesh::check_plausible_size(mesh::bounding_box(out.mesh), what + " (" + out.description + ")", diag);
  for (const auto& [name, ids] : out.named_sets)
    for (int n : ids)
      if (n < 0 || n >= out.mesh.num_nodes())
        fail(what, ": node set '", name, "' has node ", n, " outside the mesh (", out.mesh.num_nodes(), " nodes)");
  return out;
}

}  // namespace softcut::sim
