// softcut mesh info|convert|generate: inspect, convert and make tet meshes.
// Options are CLI11's (app/options.hpp), typed and validated where they are
// declared; --help is generated from the declarations. generate lives in
// cmd_mesh_generate.cpp; the bounds all three keep in mesh_limits.hpp.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <map>

#include "app/commands.hpp"
#include "app/mesh_limits.hpp"
#include "app/options.hpp"
#include "core/error.hpp"
#include "core/json_text.hpp"
#include "mesh/io/mesh_io.hpp"
#include "mesh/quality.hpp"
#include "mesh/surface.hpp"
#include "mesh/units.hpp"

namespace softcut::app {
namespace {

using namespace softcut::mesh;

struct Subcommand {
  const char* name;
  const char* usage;
  const char* summary;
  int (*run)(const Args&);
};

int cmd_info(const Args& args);
int cmd_convert(const Args& args);

const Subcommand kSubcommands[] = {
    {"info", "info FILE [--json] [--unit U]", "counts, labels, size, volume, surface and quality of a mesh", cmd_info},
    {"convert", "convert IN OUT [--unit U] [--scale S]", "convert between mesh formats (by extension), in metres",
     cmd_convert},
    {"generate", "generate KIND [options] OUT", "make a mesh: box .. upper_leg, liver, kidney, knee_ligament, "
     "surface (STL/OBJ/PLY/OFF), volume (NRRD)", cmd_mesh_generate},
};

std::string mesh_usage() {
  std::string s = "usage: softcut mesh <subcommand> ...\n\n";
  for (const Subcommand& c : kSubcommands) s += cat("  softcut mesh ", c.usage, "\n      ", c.summary, "\n");
  s += "\nFormats by extension: read .msh .node/.ele .mesh .vtk .vtu; write .vtu .msh.\n"
       "See softcut mesh <subcommand> --help.\n";
  return s;
}

// --unit U and --scale S: the file's length unit, and a factor on top.
struct Units {
  std::string unit;
  double scale = 1;
  void declare(CLI::App& app, const char* whose) {
    app.add_option("--unit", unit, cat("length unit of ", whose, " (mesh files carry none; default m)"))
        ->check(plain(CLI::IsMember({"m", "cm", "mm", "um"})))->type_name("U");
    app.add_option("--scale", scale, "every length times this (after --unit; default 1)")
        ->check(plain(CLI::PositiveNumber))->type_name("S");
  }
  double factor(const std::string& what) const { return (unit.empty() ? 1.0 : unit_metres(unit, what)) * scale; }
};

int cmd_info(const Args& args) {
  Options o("softcut mesh info",
            "Counts (nodes, tets, surface and interior nodes), labels with their tet counts, bounding box, volume,\n"
            "surface topology, element quality and the warnings from reading (a body smaller than 1 mm or larger\n"
            "than 1 m is a warning, implausible_size: usually a file in millimetres read as metres). Aspect ratio\n"
            "is R / (3 r) (1 for the regular tet); a tet is poor with a dihedral angle < 10 or > 165 degrees or\n"
            "aspect > 5.");
  CLI::App& app = o.app();
  std::string file;
  bool json = false;
  Units units;
  MeshLimits limits;
  app.add_option("file", file, "the mesh file (.msh .node/.ele .mesh .vtk .vtu)")->required()->type_name("FILE");
  app.add_flag("--json", json, "one JSON object on stdout instead of text");
  units.declare(app, "FILE");
  limits.declare(app, false);
  if (!o.parse(args)) return 0;
  const auto watchdog = limits.start("softcut mesh info");
  Diagnostics diag;
  TetMesh m = read_mesh(file, diag, limits.read());
  scale_nodes(m, units.factor("option --unit"), "option --scale");
  const Surface s = extract_surface(m);
  const auto used = referenced_nodes(m);
  const int referenced = int(std::count(used.begin(), used.end(), 1));
  const int surface_nodes = int(s.nodes.size());
  std::map<int, int> labels;
  for (int t = 0; t < m.num_tets(); ++t) ++labels[m.labels(t)];
  const SurfaceEdges edges = surface_edges(s);
  const QualityThresholds th;
  const QualityStats q = tet_quality(m, th);
  Eigen::Vector3d lo = Eigen::Vector3d::Zero(), hi = Eigen::Vector3d::Zero();
  if (m.num_nodes() > 0) lo = m.nodes.colwise().minCoeff(), hi = m.nodes.colwise().maxCoeff();
  check_plausible_size(bounding_box(m), file, diag);
  if (edges.odd > 0)
    diag.warn(file, ": surface is not a closed manifold: ", edges.odd, " surface edge(s) not in exactly two faces");
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
        {"surface", {{"faces", s.faces.rows()}, {"edges", edges.edges}, {"euler", edges.euler},
                     {"closed_manifold", edges.odd == 0}}},
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
  std::printf("surface:       %d faces, %d edges, Euler characteristic %d, %s\n", int(s.faces.rows()), edges.edges,
              edges.euler, edges.odd == 0 ? "closed manifold" : "NOT a closed manifold");
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
  Options o("softcut mesh convert",
            "Reads IN (.msh .node .ele .mesh .vtk .vtu), validates it (reorients negative tets, reports\n"
            "unreferenced nodes), converts its lengths to metres (--unit, --scale) and writes OUT (.vtu or .msh).");
  CLI::App& app = o.app();
  std::string in, out;
  Units units;
  MeshLimits limits;
  app.add_option("in", in, "the mesh to read")->required()->type_name("IN");
  app.add_option("out", out, "the mesh to write (.vtu or .msh)")->required()->type_name("OUT");
  units.declare(app, "IN");
  limits.declare(app, false);
  if (!o.parse(args)) return 0;
  const auto watchdog = limits.start("softcut mesh convert");
  Diagnostics diag;
  TetMesh m = read_mesh(in, diag, limits.read());
  scale_nodes(m, units.factor("option --unit"), "option --scale");
  check_plausible_size(bounding_box(m), out, diag);
  write_mesh(out, m);
  for (const auto& w : diag.warnings) std::fprintf(stderr, "warning: %s\n", w.c_str());
  std::printf("wrote %s: %d nodes, %d tets\n", out.c_str(), m.num_nodes(), m.num_tets());
  return 0;
}

}  // namespace

int cmd_mesh(const Args& args) {
  if (args.empty()) return std::fputs(mesh_usage().c_str(), stderr), 2;
  const std::string& sub = args[0];
  if (sub == "--help" || sub == "-h" || sub == "help") return std::fputs(mesh_usage().c_str(), stdout), 0;
  for (const Subcommand& c : kSubcommands)
    if (sub == c.name) return c.run(Args(args.begin() + 1, args.end()));
  usage_fail("softcut mesh: unknown subcommand '", sub, "' (use info, convert or generate; see softcut mesh --help)");
}

}  // namespace softcut::app
