// softcut mesh info|convert|generate: inspect, convert and make tet meshes.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <map>
#include <sstream>

#include "app/commands.hpp"
#include "core/atomic_file.hpp"
#include "core/error.hpp"
#include "core/json_text.hpp"
#include "mesh/generate/box.hpp"
#include "mesh/generate/cylinder.hpp"
#include "mesh/generate/presets.hpp"
#include "mesh/io/mesh_io.hpp"
#include "mesh/quality.hpp"
#include "mesh/surface.hpp"
#include "mesh/mesher/organs.hpp"
#include "mesh/mesher/volume_shape.hpp"
#include "mesh/volume/label_volume.hpp"
#include "sim/mesh_source.hpp"

namespace softcut::app {
namespace {

using namespace softcut::mesh;

const char* kMeshUsage =
    "usage: softcut mesh info FILE [--json]\n"
    "       softcut mesh convert IN OUT\n"
    "       softcut mesh generate KIND [options] OUT\n"
    "\n"
    "Formats by extension: read .msh .node/.ele .mesh .vtk .vtu; write .vtu .msh.\n"
    "See softcut mesh <info|convert|generate> --help.\n";

const char* kInfoUsage =
    "usage: softcut mesh info FILE [--json]\n"
    "\n"
    "Counts (nodes, tets, surface and interior nodes), labels with their tet\n"
    "counts, bounding box, volume, surface topology, element quality and the\n"
    "warnings from reading. Aspect ratio is R / (3 r) (1 for the regular tet);\n"
    "a tet is poor with a dihedral angle < 10 or > 165 degrees or aspect > 5.\n"
    "  --json   one JSON object on stdout instead of text\n";

const char* kConvertUsage =
    "usage: softcut mesh convert IN OUT\n"
    "\n"
    "Reads IN (.msh .node .ele .mesh .vtk .vtu), validates it (reorients\n"
    "negative tets, reports unreferenced nodes) and writes OUT (.vtu or .msh).\n";

const char* kGenerateUsage =
    "usage: softcut mesh generate KIND [options] OUT\n"
    "\n"
    "kinds (lengths in m; the body's axis is +z):\n"
    "  box        --size LX,LY,LZ (1,1,1)        --cells NX,NY,NZ (4,4,4)\n"
    "  cylinder   --size RADIUS,LENGTH (0.02,0.06) --cells RINGS,LAYERS\n"
    "  tube       --size RIN,ROUT,LENGTH (0.012,0.024,0.03) --cells RADIAL,AROUND,LAYERS\n"
    "             --hole-nodes FILE  write the ids of the nodes on the hole (one per line)\n"
    "  band       --size LENGTH,WIDTH,THICKNESS (0.035,0.010,0.004) --cells ALONG,ACROSS,THROUGH\n"
    "             --twist DEG (90)  --flare F (1.6, end/middle width)\n"
    "  ligament   the paper's knee ligament: a band of ~615 nodes, ~1900 tets\n"
    "  upper_leg  the paper's upper leg: a tube of ~785 nodes, ~2550 tets (accepts --hole-nodes)\n"
    "  liver, kidney, knee_ligament\n"
    "             smooth organ shapes meshed by CGAL Mesh_3 (docs/meshing.md):\n"
    "             --target-tets N (5000) or --cell-size H (m)   --scale S (1)\n"
    "             --fine-center X,Y,Z --fine-radius R --fine-ratio F (0.4): tets F x smaller near X,Y,Z\n"
    "             --lesion-radius R (liver, 0.012 m)  --lesion-center X,Y,Z (liver, 0.035,-0.005,0.02)\n"
    "             --sliver-bound DEG (12)  --seed N (1)\n"
    "  volume     tets from a segmented NRRD label image (docs/label-volume.md):\n"
    "             softcut mesh generate volume IN.nrrd|IN.nhdr [--labels 1,2] [--smooth N]\n"
    "                                   [--unit m|cm|mm|um] OUT\n"
    "             --labels L,...  labels to mesh (default: every nonzero label)\n"
    "             --smooth N      Taubin smoothing passes over the outer surface (0)\n"
    "             --mesher cgal   a smooth graded mesh by CGAL Mesh_3 instead of voxel cubes:\n"
    "                             --cell-size H (m; 2 voxels)  --sliver-bound DEG (12)\n"
    "             --unit U        length unit of the file (default: its 'space units', else mm)\n"
    "\n"
    "options for box, cylinder, tube, band, ligament, upper_leg:\n"
    "  --target-tets N, --target-nodes N   pick the resolution to meet these counts\n"
    "                                      (not for box; cell counts given replace a preset's)\n"
    "  --jitter F      move interior nodes by up to F x cell size, 0 <= F < 0.25 (0)\n"
    "  --seed N        jitter seed (1)\n"
    "  --label N       label of every tet (1)\n"
    "\n"
    "Every generator kind also takes its scenario options (s:mesh{generate = KIND, options = {...}},\n"
    "docs/lua-api.md) under the same names, '_' written '-' and vectors as X,Y,Z: box --nx 8 --max 0.1,0.05,0.05,\n"
    "tube --inner-radius 0.01 --radial 3, liver --fine-center 0,0,0.02. --size and --cells are shorthands for them.\n";

// --name value or --name=value options after the positionals are taken out.
struct Options {
  std::vector<std::string> positional;
  std::map<std::string, std::string> named;
  std::map<std::string, bool> used;

  bool has(const std::string& k) {
    used[k] = true;
    return named.count(k) > 0;
  }
  const std::string& get(const std::string& k) {
    used[k] = true;
    return named.at(k);
  }
};

Options parse_options(const Args& args, size_t from, const std::vector<std::string>& flags, const char* cmd) {
  Options o;
  for (size_t i = from; i < args.size(); ++i) {
    const std::string& a = args[i];
    if (a.size() > 2 && a.rfind("--", 0) == 0) {
      std::string key = a.substr(2), value;
      if (const size_t eq = key.find('='); eq != std::string::npos) {
        value = key.substr(eq + 1);
        key = key.substr(0, eq);
      } else if (std::find(flags.begin(), flags.end(), key) != flags.end()) {
        value = "1";
      } else {
        if (i + 1 >= args.size()) fail(cmd, ": option --", key, " needs a value");
        value = args[++i];
      }
      if (o.named.count(key)) fail(cmd, ": option --", key, " given twice");
      o.named[key] = value;
    } else {
      o.positional.push_back(a);
    }
  }
  return o;
}

bool wants_help(const Args& args) {
  return std::any_of(args.begin(), args.end(), [](const std::string& a) { return a == "--help" || a == "-h"; });
}

void reject_unused(Options& o, const std::string& cmd) {
  for (const auto& [k, v] : o.named)
    if (!o.used[k]) fail(cmd, ": unknown option --", k, " here (see softcut ", cmd, " --help)");
}

double to_double(const std::string& opt, const std::string& s) {
  char* end = nullptr;
  const double x = std::strtod(s.c_str(), &end);
  if (s.empty() || end != s.c_str() + s.size() || !std::isfinite(x))
    fail("option --", opt, ": expected a number, got '", s, "'");
  return x;
}

int to_int(const std::string& opt, const std::string& s) {
  char* end = nullptr;
  const long x = std::strtol(s.c_str(), &end, 10);
  if (s.empty() || end != s.c_str() + s.size() || std::abs(x) > 1000000000L)
    fail("option --", opt, ": expected an integer, got '", s, "'");
  return int(x);
}

std::vector<std::string> split(const std::string& s) {
  std::vector<std::string> out;
  std::stringstream ss(s);
  for (std::string x; std::getline(ss, x, ',');) out.push_back(x);
  return out;
}

std::vector<double> doubles(Options& o, const std::string& k, size_t n) {
  const auto parts = split(o.get(k));
  if (parts.size() != n) fail("option --", k, ": expected ", n, " comma-separated numbers, got '", o.get(k), "'");
  std::vector<double> v;
  for (const auto& p : parts) v.push_back(to_double(k, p));
  return v;
}

std::vector<int> ints(Options& o, const std::string& k, size_t n) {
  const auto parts = split(o.get(k));
  if (n && parts.size() != n) fail("option --", k, ": expected ", n, " comma-separated integers, got '", o.get(k), "'");
  std::vector<int> v;
  for (const auto& p : parts) v.push_back(to_int(k, p));
  return v;
}

int cmd_info(const Args& args) {
  if (wants_help(args)) return std::fputs(kInfoUsage, stdout), 0;
  Options a = parse_options(args, 1, {"json"}, "mesh info");
  const bool json = a.has("json");
  reject_unused(a, "mesh info");
  if (a.positional.size() != 1) fail("mesh info: expected one FILE (see softcut mesh info --help)");
  const std::string file = a.positional[0];
  Diagnostics diag;
  const TetMesh m = read_mesh(file, diag);
  const Surface s = extract_surface(m);
  const auto used = referenced_nodes(m);
  const int referenced = int(std::count(used.begin(), used.end(), 1));
  const int surface_nodes = int(s.nodes.size());
  std::map<int, int> labels;
  for (int t = 0; t < m.num_tets(); ++t) ++labels[m.labels(t)];
  std::map<std::pair<int, int>, int> edges;
  for (Eigen::Index f = 0; f < s.faces.rows(); ++f)
    for (int e = 0; e < 3; ++e) {
      const int p = s.faces(f, e), q = s.faces(f, (e + 1) % 3);
      ++edges[{std::min(p, q), std::max(p, q)}];
    }
  int odd_edges = 0;
  for (const auto& [e, n] : edges) odd_edges += n != 2;
  const int euler = surface_nodes - int(edges.size()) + int(s.faces.rows());
  const QualityThresholds th;
  const QualityStats q = tet_quality(m, th);
  Eigen::Vector3d lo = Eigen::Vector3d::Zero(), hi = Eigen::Vector3d::Zero();
  if (m.num_nodes() > 0) lo = m.nodes.colwise().minCoeff(), hi = m.nodes.colwise().maxCoeff();
  if (odd_edges > 0)
    diag.warn(file, ": surface is not a closed manifold: ", odd_edges, " surface edge(s) not in exactly two faces");
  if (q.num_poor > 0)
    diag.warn(file, ": ", q.num_poor, " poor tetrahedra (worst: tet ", q.worst_tet, ", aspect ", q.max_aspect, ")");

  if (json) {
    Json labs = Json::array();
    for (const auto& [l, n] : labels) labs.push_back({{"label", l}, {"tets", n}});
    auto vec = [](const Eigen::Vector3d& v) { return Json{json_number(v.x()), json_number(v.y()), json_number(v.z())}; };
    const Json j = {
        {"file", file}, {"nodes", m.num_nodes()}, {"referenced_nodes", referenced}, {"surface_nodes", surface_nodes},
        {"interior_nodes", referenced - surface_nodes}, {"tets", m.num_tets()}, {"labels", std::move(labs)},
        {"bbox_min", vec(lo)}, {"bbox_max", vec(hi)}, {"volume", json_number(q.total_volume)},
        {"surface", {{"faces", s.faces.rows()}, {"edges", edges.size()}, {"euler", euler},
                     {"closed_manifold", odd_edges == 0}}},
        {"quality", {{"min_volume", json_number(q.min_volume)}, {"max_volume", json_number(q.max_volume)},
                     {"min_dihedral_deg", json_number(q.min_dihedral_deg)},
                     {"max_dihedral_deg", json_number(q.max_dihedral_deg)}, {"min_aspect", json_number(q.min_aspect)},
                     {"mean_aspect", json_number(q.mean_aspect)}, {"max_aspect", json_number(q.max_aspect)},
                     {"min_edge", json_number(q.min_edge)}, {"max_edge", json_number(q.max_edge)},
                     {"nonpositive", q.num_nonpositive}, {"small_dihedral", q.num_small_dihedral},
                     {"large_dihedral", q.num_large_dihedral}, {"high_aspect", q.num_high_aspect},
                     {"poor", q.num_poor}}},
        {"warnings", diag.warnings}};
    std::fputs(json_text(j).c_str(), stdout);
    return 0;
  }
  std::printf("file:          %s\n", file.c_str());
  std::printf("nodes:         %d (%d surface, %d interior, %d unreferenced)\n", m.num_nodes(), surface_nodes,
              referenced - surface_nodes, m.num_nodes() - referenced);
  std::printf("tets:          %d\n", m.num_tets());
  std::printf("labels:       ");
  for (const auto& [l, n] : labels) std::printf(" %d (%d tets)", l, n);
  std::printf("\n");
  std::printf("bounding box:  [%.6g, %.6g, %.6g] .. [%.6g, %.6g, %.6g] m\n", lo.x(), lo.y(), lo.z(), hi.x(), hi.y(),
              hi.z());
  std::printf("volume:        %.6g m^3\n", q.total_volume);
  std::printf("surface:       %d faces, %d edges, Euler characteristic %d, %s\n", int(s.faces.rows()),
              int(edges.size()), euler, odd_edges == 0 ? "closed manifold" : "NOT a closed manifold");
  if (m.num_tets() > 0) {
    std::printf("tet volume:    %.4g .. %.4g m^3\n", q.min_volume, q.max_volume);
    std::printf("edge length:   %.4g .. %.4g m\n", q.min_edge, q.max_edge);
    std::printf("dihedral:      %.2f .. %.2f deg\n", q.min_dihedral_deg, q.max_dihedral_deg);
    std::printf("aspect R/3r:   %.3f min, %.3f mean, %.3f max\n", q.min_aspect, q.mean_aspect, q.max_aspect);
    std::printf("poor tets:     %d (dihedral < %g deg: %d, > %g deg: %d, aspect > %g: %d, non-positive: %d)\n",
                q.num_poor, th.min_dihedral_deg, q.num_small_dihedral, th.max_dihedral_deg, q.num_large_dihedral,
                th.max_aspect, q.num_high_aspect, q.num_nonpositive);
  }
  for (const auto& w : diag.warnings) std::printf("warning: %s\n", w.c_str());
  return 0;
}

int cmd_convert(const Args& args) {
  if (wants_help(args)) return std::fputs(kConvertUsage, stdout), 0;
  Options a = parse_options(args, 1, {}, "mesh convert");
  reject_unused(a, "mesh convert");
  if (a.positional.size() != 2) fail("mesh convert: expected IN and OUT (see softcut mesh convert --help)");
  Diagnostics diag;
  const TetMesh m = read_mesh(a.positional[0], diag);
  write_mesh(a.positional[1], m);
  for (const auto& w : diag.warnings) std::fprintf(stderr, "warning: %s\n", w.c_str());
  std::printf("wrote %s: %d nodes, %d tets\n", a.positional[1].c_str(), m.num_nodes(), m.num_tets());
  return 0;
}

void write_hole_nodes(const std::string& path, const std::string& mesh_path, const std::vector<int>& ids) {
  write_file_atomic(path, [&](std::ostream& os) {
    os << "# node ids (0-based) on the hole surface of " << mesh_path << ", one per line\n";
    for (int i : ids) os << i << "\n";
  });
}

// The command line's spelling of a scenario generator's options, whose one
// list is sim/mesh_source's: --target-tets N is target_tets, --fine-center
// X,Y,Z is fine_center.x/.y/.z; the structured kinds also take --size and
// --cells (their dimensions and cell counts at once) and band --twist.
struct Shorthand {
  const char* family;  // box, cylinder, tube (upper_leg), band (ligament)
  const char* option;
  std::vector<const char*> names;
};

const std::vector<Shorthand>& shorthands() {
  static const std::vector<Shorthand> s = {
      {"box", "size", {"max.x", "max.y", "max.z"}},
      {"box", "cells", {"nx", "ny", "nz"}},
      {"cylinder", "size", {"radius", "length"}},
      {"cylinder", "cells", {"rings", "layers"}},
      {"tube", "size", {"inner_radius", "outer_radius", "length"}},
      {"tube", "cells", {"radial", "around", "layers"}},
      {"band", "size", {"length", "width", "thickness"}},
      {"band", "cells", {"along", "across", "through"}},
      {"band", "twist", {"twist_deg"}},
  };
  return s;
}

// A generator's options as the command line spells them (for messages).
std::string cli_spelling(const std::string& family, const std::vector<std::string>& known) {
  std::string out;
  auto add = [&](const std::string& o) { out += (out.empty() ? "--" : ", --") + o; };
  for (const Shorthand& sh : shorthands())
    if (family == sh.family) add(sh.option);
  for (std::string n : known) {
    if (n.size() > 2 && n[n.size() - 2] == '.' && n.back() != 'x') continue;  // .y, .z: with .x
    const bool vec = n.size() > 2 && n.substr(n.size() - 2) == ".x";
    if (vec) n.resize(n.size() - 2);
    std::replace(n.begin(), n.end(), '_', '-');
    add(vec ? n + " X,Y,Z" : n);
  }
  return out;
}

sim::MeshSource generator_source(const std::string& kind, Options& a) {
  const std::string family = kind == "upper_leg" ? "tube" : kind == "ligament" ? "band" : kind;
  const std::vector<std::string> known = sim::generator_options(kind);
  auto knows = [&](const std::string& n) { return std::find(known.begin(), known.end(), n) != known.end(); };
  sim::MeshSource src;
  src.generator = kind;
  std::map<std::string, std::string> set_by;  // generator option -> the command-line option that set it
  auto set = [&](const std::string& key, const std::string& name, double v) {
    if (const auto [it, fresh] = set_by.emplace(name, key); !fresh)
      fail("mesh generate ", kind, ": --", it->second, " and --", key, " both set ", name, "; give one of them");
    src.options[name] = v;
  };
  for (const auto& entry : a.named) {
    const std::string& key = entry.first;  // (not a structured binding: lambdas capture it below)
    const std::string& value = entry.second;
    if (key == "hole-nodes") continue;
    a.used[key] = true;
    const auto sh = std::find_if(shorthands().begin(), shorthands().end(),
                                 [&](const Shorthand& x) { return family == x.family && key == x.option; });
    std::string name = key;
    std::replace(name.begin(), name.end(), '-', '_');
    if (sh != shorthands().end()) {
      const auto v = doubles(a, key, sh->names.size());
      for (size_t i = 0; i < v.size(); ++i) set(key, sh->names[i], v[i]);
    } else if (knows(name + ".x")) {
      const auto v = doubles(a, key, 3);
      for (int i = 0; i < 3; ++i) set(key, name + "." + "xyz"[i], v[size_t(i)]);
    } else if (knows(name)) {
      set(key, name, to_double(key, value));
    } else {
      fail("mesh generate ", kind, ": unknown option --", key, " (", kind, " takes ", cli_spelling(family, known),
           "; see softcut mesh generate --help)");
    }
  }
  return src;
}

int cmd_generate(const Args& args) {
  if (args.size() < 2) return std::fputs(kGenerateUsage, stderr), 2;
  if (wants_help(args)) return std::fputs(kGenerateUsage, stdout), 0;
  const std::string kind = args[1];
  static const char* kKinds[] = {"box", "cylinder", "tube", "band", "ligament", "upper_leg", "volume"};
  const auto& organs = organ_kinds();
  const bool organ = std::find(organs.begin(), organs.end(), kind) != organs.end();
  if (!organ && std::find(std::begin(kKinds), std::end(kKinds), kind) == std::end(kKinds))
    fail("mesh generate: unknown kind '", kind,
         "' (use box, cylinder, tube, band, ligament, upper_leg, liver, kidney, knee_ligament or volume;"
         " see softcut mesh generate --help)");
  Options a = parse_options(args, 2, {}, "mesh generate");
  Diagnostics diag;
  TetMesh m;
  std::string note;
  std::vector<int> hole;
  if (kind != "tube" && kind != "upper_leg" && a.named.count("hole-nodes"))
    fail("mesh generate ", kind, ": --hole-nodes is only for tube and upper_leg");
  if (kind == "volume") {
    std::string in;
    if (a.has("input")) in = a.get("input");
    if (a.positional.size() == 2 && in.empty()) in = a.positional[0];
    if (in.empty() || a.positional.size() != (a.has("input") ? 1u : 2u))
      fail("mesh generate volume: expected IN.nrrd (or --input IN) and OUT (see softcut mesh generate --help)");
    NrrdReadOptions ro;
    if (a.has("unit")) {
      const std::string u = a.get("unit");
      ro.unit_m = u == "m" ? 1 : u == "cm" ? 1e-2 : u == "mm" ? 1e-3 : u == "um" ? 1e-6 : 0;
      if (ro.unit_m == 0) fail("option --unit: expected m, cm, mm or um, got '", u, "'");
    }
    VoxelMeshOptions vo;
    if (a.has("labels")) vo.labels = ints(a, "labels", 0);
    const std::string mesher = a.has("mesher") ? a.get("mesher") : "voxels";
    if (mesher != "voxels" && mesher != "cgal") fail("option --mesher: expected voxels or cgal, got '", mesher, "'");
    const LabelVolume v = read_nrrd_labels(in, diag, ro);
    note = cat("volume ", v.size(0), " x ", v.size(1), " x ", v.size(2), " voxels from ", in);
    if (mesher == "cgal") {
      MesherOptions mo;
      mo.cell_size = 2 * v.directions.colwise().norm().maxCoeff();
      if (a.has("cell-size")) mo.cell_size = to_double("cell-size", a.get("cell-size"));
      if (a.has("sliver-bound")) mo.sliver_bound_deg = to_double("sliver-bound", a.get("sliver-bound"));
      MesherReport r;
      m = mesh_shape(volume_shape(v, vo.labels), mo, &r);
      note += cat("; CGAL Mesh_3, cell size ", mo.cell_size, " m, min dihedral ", std::round(r.min_dihedral_deg * 10) / 10, " deg");
    } else {
      if (a.has("smooth")) vo.smooth_iterations = to_int("smooth", a.get("smooth"));
      if (vo.smooth_iterations < 0) fail("option --smooth: must be >= 0");
      m = mesh_label_volume(v, vo, diag);
    }
  } else {
    if (a.positional.size() != 1) fail("mesh generate ", kind, ": expected exactly one OUT file after the options");
    const sim::LoadedMesh loaded = sim::load_mesh_source(generator_source(kind, a), diag);
    m = loaded.mesh;
    note = loaded.description;
    if (auto it = loaded.named_sets.find("hole"); it != loaded.named_sets.end()) hole = it->second;
  }
  const bool want_hole = a.has("hole-nodes");
  reject_unused(a, "mesh generate");
  const std::string out = a.positional.back();
  validate(m, "generated " + kind, diag);
  write_mesh(out, m);
  if (want_hole) {
    write_hole_nodes(a.get("hole-nodes"), out, hole);
    note += cat("; ", hole.size(), " hole-surface node ids in ", a.get("hole-nodes"));
  }
  for (const auto& w : diag.warnings) std::fprintf(stderr, "warning: %s\n", w.c_str());
  std::printf("wrote %s: %d nodes, %d tets (%s)\n", out.c_str(), m.num_nodes(), m.num_tets(), note.c_str());
  return 0;
}

}  // namespace

int cmd_mesh(const Args& args) {
  if (args.empty()) return std::fputs(kMeshUsage, stderr), 2;
  const std::string& sub = args[0];
  if (sub == "--help" || sub == "-h" || sub == "help") return std::fputs(kMeshUsage, stdout), 0;
  if (sub == "info") return cmd_info(args);
  if (sub == "convert") return cmd_convert(args);
  if (sub == "generate") return cmd_generate(args);
  fail("mesh: unknown subcommand '", sub, "' (use info, convert or generate; see softcut mesh --help)");
}

}  // namespace softcut::app
