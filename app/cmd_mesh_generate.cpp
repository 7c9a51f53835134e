// softcut mesh generate KIND [options] OUT. Every generator kind takes its
// scenario options (sim/mesh_source.hpp: s:mesh{ generate = KIND, options =
// {...} }) under the same names, '_' written '-' and vectors as X,Y,Z: each
// is declared here from the generator's own list, with its default and help
// line, so `softcut mesh generate KIND --help` shows what KIND takes.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <map>
#include <memory>
#include <sstream>

#include "app/commands.hpp"
#include "app/mesh_limits.hpp"
#include "app/options.hpp"
#include "core/atomic_file.hpp"
#include "core/error.hpp"
#include "mesh/io/mesh_io.hpp"
#include "mesh/io/surface_io.hpp"
#include "mesh/mesher/organs.hpp"
#include "mesh/mesher/volume_shape.hpp"
#include "mesh/units.hpp"
#include "mesh/volume/label_volume.hpp"
#include "sim/mesh_source.hpp"

namespace softcut::app {
namespace {

using namespace softcut::mesh;

enum class Family { box, cylinder, tube, band, organ, surface, volume };

struct Kind {
  const char* name;
  Family family;
  const char* summary;
};

const Kind kKinds[] = {
    {"box", Family::box, "an axis-aligned box of cubes, each split into 6 tets"},
    {"cylinder", Family::cylinder, "a cylinder along +z, rings of cells around its axis"},
    {"tube", Family::tube, "a thick tube with a coaxial hole, along +z"},
    {"band", Family::band, "a flat band along +z, flared to its ends and twisted"},
    {"ligament", Family::band, "the paper's knee ligament: a band of ~615 nodes, ~1900 tets"},
    {"upper_leg", Family::tube, "the paper's upper leg: a tube of ~785 nodes, ~2550 tets"},
    {"liver", Family::organ, "a two-lobed liver with a lesion (label 2), meshed by CGAL Mesh_3 (docs/meshing.md)"},
    {"kidney", Family::organ, "a kidney: cortex (label 1) and medulla (label 2), meshed by CGAL Mesh_3"},
    {"knee_ligament", Family::organ, "the paper's ligament as the tissue looks, meshed by CGAL Mesh_3"},
    {"surface", Family::surface, "closed surfaces (STL, OBJ, PLY, OFF): the organ, then inner regions as labels 2, "
     "3, ...; meshed by CGAL Mesh_3, sharp edges kept"},
    {"volume", Family::volume, "a segmented NRRD label image: voxel cubes, or smooth by CGAL (--mesher cgal) "
     "(docs/label-volume.md)"},
};

// --size and --cells set a structured kind's dimensions and cell counts at
// once.
struct Shorthand {
  Family family;
  const char* option;
  const char* help;
  std::vector<const char*> names;
};

const std::vector<Shorthand>& shorthands() {
  static const std::vector<Shorthand> s = {
      {Family::box, "size", "LX,LY,LZ: max corner with min at 0, m", {"max.x", "max.y", "max.z"}},
      {Family::box, "cells", "NX,NY,NZ", {"nx", "ny", "nz"}},
      {Family::cylinder, "size", "RADIUS,LENGTH, m", {"radius", "length"}},
      {Family::cylinder, "cells", "RINGS,LAYERS", {"rings", "layers"}},
      {Family::tube, "size", "RIN,ROUT,LENGTH, m", {"inner_radius", "outer_radius", "length"}},
      {Family::tube, "cells", "RADIAL,AROUND,LAYERS", {"radial", "around", "layers"}},
      {Family::band, "size", "LENGTH,WIDTH,THICKNESS, m", {"length", "width", "thickness"}},
      {Family::band, "cells", "ALONG,ACROSS,THROUGH", {"along", "across", "through"}},
  };
  return s;
}

// "a,b,c" -> numbers (the count is checked by the caller).
std::vector<double> numbers(const std::string& text) {
  std::vector<double> v;
  std::stringstream ss(text);
  for (std::string x; std::getline(ss, x, ',');) {
    char* end = nullptr;
    const double d = std::strtod(x.c_str(), &end);
    v.push_back(!x.empty() && end == x.c_str() + x.size() && std::isfinite(d) ? d : NAN);
  }
  return v;
}

CLI::Validator n_numbers(std::size_t n) {
  return CLI::Validator(
      [n](std::string& s) {
        const auto v = numbers(s);
        const bool ok = v.size() == n && std::all_of(v.begin(), v.end(), [](double x) { return std::isfinite(x); });
        return ok ? std::string() : cat("expected ", n, " comma-separated numbers, got '", s, "'");
      },
      "");
}

std::string short_number(double v) {
  std::ostringstream os;
  os.precision(6);
  os << v;
  return os.str();
}

std::string kinds_help() {
  std::string s = "usage: softcut mesh generate KIND [options] OUT\n\nkinds (lengths in m; the body's axis is +z):\n";
  for (const Kind& k : kKinds) {
    char line[256];
    std::snprintf(line, sizeof line, "  %-14s %s\n", k.name, k.summary);
    s += line;
  }
  s += "\nsoftcut mesh generate KIND --help lists the options KIND takes: its scenario options\n"
       "(s:mesh{generate = KIND, options = {...}}, docs/lua-api.md) under the same names, '_' written '-'\n"
       "and vectors as X,Y,Z (box --nx 8 --max 0.1,0.05,0.05; liver --fine-center 0,0,0.02).\n";
  return s;
}

// The generator options of `kind` declared on `app`: values land in `given`
// (as text; vectors whole) when the option is on the command line.
struct GeneratorOptions {
  std::map<std::string, std::string> text;  // command-line name -> value
  std::map<std::string, std::vector<std::string>> names;  // command-line name -> generator option names
};

void declare_generator(CLI::App& app, const std::string& kind, Family family, GeneratorOptions& g) {
  const auto defaults = sim::generator_defaults(kind);
  for (const Shorthand& sh : shorthands()) {
    if (sh.family != family) continue;
    std::vector<std::string> n(sh.names.begin(), sh.names.end());
    std::string def;
    for (const auto& x : n) def += (def.empty() ? "" : ",") + short_number(defaults.count(x) ? defaults.at(x) : 0);
    g.names[sh.option] = n;
    app.add_option("--" + std::string(sh.option), g.text[sh.option], cat(sh.help, " (", def, ")"))
        ->check(n_numbers(sh.names.size()))->type_name(sh.names.size() > 1 ? "A,B,C" : "X");
  }
  for (const std::string& name : sim::generator_options(kind)) {
    const bool axis = name.size() > 2 && name[name.size() - 2] == '.';
    if (axis && name.back() != 'x') continue;  // .y, .z: with .x
    const std::string base = axis ? name.substr(0, name.size() - 2) : name;
    std::string cli = base;
    std::replace(cli.begin(), cli.end(), '_', '-');
    std::string def = short_number(defaults.at(name));
    if (axis) def += "," + short_number(defaults.at(base + ".y")) + "," + short_number(defaults.at(base + ".z"));
    g.names[cli] = axis ? std::vector<std::string>{base + ".x", base + ".y", base + ".z"} : std::vector<std::string>{name};
    app.add_option("--" + cli, g.text[cli], cat(sim::generator_option_help(base), " (", def, ")"))
        ->check(axis ? vec3_text() : number_text())->type_name(axis ? "X,Y,Z" : "N");
  }
}

// The scenario's option map from what was given; one value per option.
std::map<std::string, double> generator_values(const CLI::App& app, const std::string& kind, GeneratorOptions& g) {
  std::map<std::string, double> out;
  std::map<std::string, std::string> set_by;  // generator option -> the command-line option that set it
  for (const auto& [cli, names] : g.names) {
    if (app.count("--" + cli) == 0) continue;
    const auto v = numbers(g.text[cli]);
    for (std::size_t i = 0; i < names.size(); ++i) {
      if (const auto [it, fresh] = set_by.emplace(names[i], cli); !fresh)
        usage_fail("softcut mesh generate ", kind, ": --", it->second, " and --", cli, " both set ", names[i],
                   "; give one of them");
      out[names[i]] = v[i];
    }
  }
  return out;
}

void write_hole_nodes(const std::string& path, const std::string& mesh_path, const std::vector<int>& ids) {
  write_file_atomic(path, [&](std::ostream& os) {
    os << "# node ids (0-based) on the hole surface of " << mesh_path << ", one per line\n";
    for (int i : ids) os << i << "\n";
  });
}

// volume: an NRRD label image, as voxel cubes or through CGAL.
struct VolumeOptions {
  std::string input, unit, mesher = "voxels";
  std::vector<int> labels;
  int smooth = 0;
  double cell_size = 0, sliver_bound = 12;
  void declare(CLI::App& app) {
    app.add_option("--input", input, "the NRRD label image (instead of the first positional IN)")->type_name("IN");
    app.add_option("--labels", labels, "labels to mesh (default: every nonzero label)")->delimiter(',')
        ->allow_extra_args(false)->type_name("L,...");
    app.add_option("--smooth", smooth, cat("Taubin smoothing passes over the outer surface, 0..", kMaxSmoothIterations,
                                           " (0; voxels only)"))
        ->check(plain(CLI::Range(0, kMaxSmoothIterations)))->type_name("N");
    app.add_option("--mesher", mesher, "voxels: cubes of 6 tets; cgal: a smooth graded mesh by CGAL Mesh_3")
        ->check(plain(CLI::IsMember({"voxels", "cgal"})))->type_name("M");
    app.add_option("--cell-size", cell_size, "cgal: the local cell size h, m (2 voxels)")->check(plain(CLI::PositiveNumber))
        ->type_name("H");
    app.add_option("--sliver-bound", sliver_bound, "cgal: degrees; lift every dihedral angle above it (12)")
        ->check(plain(CLI::Range(0.0, 29.99)))->type_name("DEG");
    app.add_option("--unit", unit, "length unit of the image (default: its 'space units', else mm)")
        ->check(plain(CLI::IsMember({"m", "cm", "mm", "um"})))->type_name("U");
  }
};

}  // namespace

int cmd_mesh_generate(const Args& args) {
  if (args.empty()) return std::fputs(kinds_help().c_str(), stderr), 2;
  const std::string& name = args[0];
  if (name == "--help" || name == "-h") return std::fputs(kinds_help().c_str(), stdout), 0;
  const auto kind_it = std::find_if(std::begin(kKinds), std::end(kKinds), [&](const Kind& k) { return name == k.name; });
  if (kind_it == std::end(kKinds))
    usage_fail("softcut mesh generate: unknown kind '", name,
               "' (use box, cylinder, tube, band, ligament, upper_leg, liver, kidney, knee_ligament, surface or volume;"
               " see softcut mesh generate --help)");
  const Kind& kind = *kind_it;
  const std::string command = "softcut mesh generate " + name;
  Options o(command, cat(kind.summary, "."),
            "Every length is in metres. Exit status: 0 done, 1 an error, 2 usage, 124 wall-clock limit (--timeout).");
  CLI::App& app = o.app();
  std::vector<std::string> files;
  const char* positional = kind.family == Family::surface ? "IN... OUT"
                           : kind.family == Family::volume ? "IN OUT"
                                                            : "OUT";
  app.add_option("files", files, kind.family == Family::surface
                                     ? "the closed surfaces (.stl .obj .ply .off; the organ first), then the mesh to write"
                                     : kind.family == Family::volume ? "the NRRD label image, then the mesh to write"
                                                                     : "the mesh to write (.vtu or .msh)")
      ->type_name(positional);
  GeneratorOptions gen;
  VolumeOptions vol;
  std::string hole_nodes, surface_unit;
  MeshLimits limits;
  if (kind.family == Family::volume) {
    vol.declare(app);
  } else {
    declare_generator(app, name, kind.family, gen);
  }
  if (kind.family == Family::tube)
    app.add_option("--hole-nodes", hole_nodes, "write the ids of the nodes on the hole, one per line")->type_name("FILE");
  if (kind.family == Family::surface)
    app.add_option("--unit", surface_unit, "length unit of the surfaces (default: guessed from their size, said "
                   "on stderr: m up to 1, mm up to 1000)")
        ->check(plain(CLI::IsMember({"m", "cm", "mm", "um"})))->type_name("U");
  limits.declare(app, true);
  try {
    if (!o.parse(args.size() > 1 ? Args(args.begin() + 1, args.end()) : Args{})) return 0;
  } catch (const UsageError& e) {
    // An unknown option: say what this kind takes, as the command line spells it.
    const std::string m = e.what();
    if (m.find("unknown option") == std::string::npos) throw;
    std::string takes;
    for (const CLI::Option* opt : app.get_options())
      if (!opt->get_lnames().empty() && opt->get_lnames()[0] != "help")
        takes += (takes.empty() ? "--" : ", --") + opt->get_lnames()[0] +
                 (opt->get_type_name() == "X,Y,Z" ? std::string(" X,Y,Z") : std::string());
    usage_fail(m, "; ", name, " takes ", takes);
  }
  const auto watchdog = limits.start(command);

  Diagnostics diag;
  TetMesh m;
  std::string note;
  std::vector<int> hole;
  const std::string see = " (see " + command + " --help)";
  if (kind.family == Family::volume) {
    if (!vol.input.empty()) files.insert(files.begin(), vol.input);
    if (files.size() != 2) usage_fail(command, ": expected IN.nrrd (or --input IN) and OUT", see);
    if (vol.mesher == "cgal" && app.count("--smooth")) usage_fail(command, ": --smooth is for --mesher voxels", see);
    if (vol.mesher != "cgal" && (app.count("--cell-size") || app.count("--sliver-bound")))
      usage_fail(command, ": --cell-size and --sliver-bound are for --mesher cgal", see);
    NrrdReadOptions ro;
    if (!vol.unit.empty()) ro.unit_m = unit_metres(vol.unit, "option --unit");
    ro.max_bytes = limits.volume_bytes();
    VoxelMeshOptions vo;
    vo.labels = vol.labels;
    vo.smooth_iterations = vol.smooth;
    vo.max_tets = limits.max_tets;
    vo.raise = MeshLimits::raise_tets();
    const LabelVolume v = read_nrrd_labels(files[0], diag, ro);
    note = cat("volume ", v.size(0), " x ", v.size(1), " x ", v.size(2), " voxels from ", files[0]);
    if (vol.mesher == "cgal") {
      MesherOptions mo;
      mo.cell_size = app.count("--cell-size") ? vol.cell_size : 2 * v.directions.colwise().norm().maxCoeff();
      mo.sliver_bound_deg = vol.sliver_bound;
      mo.max_vertices = max_vertices_for(limits.max_tets);
      mo.stop = &watchdog->expired();
      const LabeledShape shape = volume_shape(v, vo.labels);
      MeshLimit limit;
      limit.max_tets = limits.max_tets;
      limit.raise = MeshLimits::raise_tets();
      if (const double estimate = estimate_tets(shape, mo); !(estimate <= limits.max_tets))
        fail(shape.name, ": ", over_limit(estimate, limit));
      MesherReport r;
      m = mesh_shape(shape, mo, &r);
      note += cat("; CGAL Mesh_3, cell size ", mo.cell_size, " m, min dihedral ", std::round(r.min_dihedral_deg * 10) / 10, " deg");
    } else {
      m = mesh_label_volume(v, vo, diag);
    }
  } else {
    const std::size_t want = kind.family == Family::surface ? 2 : 1;
    if (files.size() < want || (kind.family != Family::surface && files.size() != 1))
      usage_fail(command, ": expected ", kind.family == Family::surface ? "IN.stl [IN2 ...] and OUT" : "exactly one OUT file",
                 " after the options", see);
    sim::MeshSource src;
    src.generator = name;
    src.options = generator_values(app, name, gen);
    src.stop = &watchdog->expired();
    src.raise_limit = MeshLimits::raise_tets();
    if (kind.family == Family::surface) {
      src.surfaces.assign(files.begin(), files.end() - 1);
      src.unit = surface_unit;
    }
    const sim::LoadedMesh loaded = sim::load_mesh_source(src, diag, limits.max_tets, limits.read());
    m = loaded.mesh;
    note = loaded.description;
    if (auto it = loaded.named_sets.find("hole"); it != loaded.named_sets.end()) hole = it->second;
  }
  const std::string out = files.back();
  validate(m, "generated " + name, diag);
  write_mesh(out, m);
  if (!hole_nodes.empty()) {
    write_hole_nodes(hole_nodes, out, hole);
    note += cat("; ", hole.size(), " hole-surface node ids in ", hole_nodes);
  }
  for (const auto& w : diag.warnings) std::fprintf(stderr, "warning: %s\n", w.c_str());
  std::printf("wrote %s: %d nodes, %d tets (%s)\n", out.c_str(), m.num_nodes(), m.num_tets(), note.c_str());
  return 0;
}

}  // namespace softcut::app
