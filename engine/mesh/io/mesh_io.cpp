#include "mesh/io/mesh_io.hpp"

#include <algorithm>
#include <cctype>
#include <climits>
#include <cmath>

#include "core/checked_file.hpp"
#include "core/printable.hpp"
#include "mesh/io/formats.hpp"
#include "mesh/io/vtu_writer.hpp"

namespace softcut::mesh {

namespace {
std::string lower_extension(const std::filesystem::path& p) {
  std::string e = p.extension().string();
  std::transform(e.begin(), e.end(), e.begin(), [](unsigned char c) { return char(std::tolower(c)); });
  return e;
}
}  // namespace

namespace {
TetMesh read_mesh_unescaped(const std::filesystem::path& path, Diagnostics& diag, const ReadOptions& opt) {
  const std::string source = path.string();
  const std::string ext = lower_extension(path);
  TetMesh m;
  if (ext == ".node" || ext == ".ele") {
    std::filesystem::path node = path, ele = path;
    node.replace_extension(ext == ".node" ? path.extension() : std::filesystem::path(".node"));
    ele.replace_extension(ext == ".ele" ? path.extension() : std::filesystem::path(".ele"));
    m = io::read_tetgen(node, ele, diag, opt);
  } else if (ext == ".msh" || ext == ".mesh" || ext == ".vtk" || ext == ".vtu") {
    const std::string text = io::read_file(path, opt);
    if (ext == ".msh") m = io::read_gmsh(source, text, diag);
    else if (ext == ".mesh") m = io::read_medit(source, text, diag);
    else if (ext == ".vtk") m = io::read_vtk(source, text, diag);
    else m = io::read_vtu(source, text, diag, opt.max_bytes);
  } else {
    fail(source, ": unknown mesh file extension '", path.extension().string(),
         "'; supported: .msh (Gmsh ASCII 1, 2.2, 4.1), .node/.ele (TetGen), .mesh (medit), "
         ".vtk (legacy VTK unstructured grid), .vtu (VTK XML unstructured grid)");
  }
  if (m.num_tets() == 0)
    fail(source, ": the file holds no tetrahedra (", m.num_nodes(), " nodes); softcut needs a volume mesh");
  validate(m, source, diag);
  return m;
}

}  // namespace

TetMesh read_mesh(const std::filesystem::path& path, Diagnostics& diag, const ReadOptions& opt) {
  // Messages quote the file's bytes: shown escaped (no terminal escape
  // sequences, no NUL cutting a message short), whichever reader made them.
  try {
    return read_mesh_unescaped(path, diag, opt);
  } catch (const Error& e) {
    throw Error(printable(e.what(), 4000));
  }
}

void write_mesh(const std::filesystem::path& path, const TetMesh& m) {
  const std::string ext = lower_extension(path);
  if (m.labels.size() != 0 && m.labels.size() != m.tets.rows())
    fail(path.string(), ": cannot write a mesh with ", m.labels.size(), " labels for ", m.tets.rows(), " tetrahedra");
  if (ext == ".vtu") (void)io::write_vtu(path, m);
  else if (ext == ".msh") io::write_gmsh(path, m);
  else
    fail(path.string(), ": cannot write mesh files with extension '", path.extension().string(),
         "'; supported: .vtu (VTK XML), .msh (Gmsh 2.2 ASCII)");
}

namespace io {

std::string read_file(const std::filesystem::path& path, const ReadOptions& opt) {
  if (!opt.root.empty()) {
    const std::filesystem::path rel = relative_below(opt.root, path);
    if (rel.empty())
      fail(printable(path.string()), ": outside the scenario's folder ", printable(opt.root.string()),
           " (the sandbox reads only below it; run with --trust to lift this)");
    // A text mesh decodes to up to ~8x its size (doubles and ints per
    // token, validation copies): the file itself may take an eighth.
    return read_below(opt.root, rel, "mesh file", opt.max_bytes / 8);
  }
  std::error_code ec;
  if (!std::filesystem::is_regular_file(path, ec))
    fail(path.string(), ": no such file (or not a regular file)");
  return read_regular_file(path, "the mesh file", opt.max_bytes);
}

TetMesh MeshBuffers::finish() const {
  TetMesh m;
  const Eigen::Index nn = Eigen::Index(xyz.size() / 3), nt = Eigen::Index(tet.size() / 4);
  m.nodes.resize(nn, 3);
  for (Eigen::Index i = 0; i < nn; ++i)
    for (int c = 0; c < 3; ++c) m.nodes(i, c) = xyz[std::size_t(3 * i + c)];
  m.tets.resize(nt, 4);
  for (Eigen::Index t = 0; t < nt; ++t)
    for (int k = 0; k < 4; ++k) m.tets(t, k) = tet[std::size_t(4 * t + k)];
  m.labels = label.empty() ? Eigen::VectorXi::Zero(nt) : Eigen::Map<const Eigen::VectorXi>(label.data(), Eigen::Index(label.size())).eval();
  return m;
}

void SkippedElements::report(const std::string& source, Diagnostics& diag) const {
  if (count.empty()) return;
  std::int64_t total = 0;
  std::string kinds;
  for (const auto& [kind, n] : count) {
    total += n;
    kinds += cat(kinds.empty() ? "" : ", ", n, " ", kind);
  }
  diag.warn(source, ": skipped ", total, " element(s) that are not linear tetrahedra (", kinds, ")");
}

int label_name_rank(std::string_view name) {
  static const char* kNames[] = {"label", "labels", "region", "regions", "gmsh:physical", "cellentityids",
                                 "medit:ref", "material", "materialids"};
  std::string n(name);
  std::transform(n.begin(), n.end(), n.begin(), [](unsigned char c) { return char(std::tolower(c)); });
  for (int i = 0; i < int(std::size(kNames)); ++i)
    if (n == kNames[i]) return i;
  return -1;
}

bool label_value_ok(double v) { return std::isfinite(v) && v == std::floor(v) && v >= INT_MIN && v <= INT_MAX; }

}  // namespace io
}  // namespace softcut::mesh
