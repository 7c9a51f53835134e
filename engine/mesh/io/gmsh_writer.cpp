// Gmsh 2.2 ASCII writer: node tags 1..n in id order, tetrahedra (type 4) with
// the label as both physical and elementary tag. Coordinates are written in
// the shortest form that reads back to the same double.
#include <charconv>

#include "core/atomic_file.hpp"
#include "mesh/io/formats.hpp"

namespace softcut::mesh::io {

void write_gmsh(const std::filesystem::path& path, const TetMesh& m) {
  const int nn = m.num_nodes(), nt = m.num_tets();
  std::string out;
  out.reserve(std::size_t(nn) * 64 + std::size_t(nt) * 48 + 128);
  auto put_double = [&](double v) {
    char buf[32];
    const auto r = std::to_chars(buf, buf + sizeof buf, v);
    out.append(buf, r.ptr);
  };
  out += "$MeshFormat\n2.2 0 8\n$EndMeshFormat\n$Nodes\n";
  out += std::to_string(nn) + "\n";
  for (int i = 0; i < nn; ++i) {
    out += std::to_string(i + 1);
    for (int c = 0; c < 3; ++c) {
      out += ' ';
      put_double(m.nodes(i, c));
    }
    out += '\n';
  }
  out += "$EndNodes\n$Elements\n" + std::to_string(nt) + "\n";
  for (int t = 0; t < nt; ++t) {
    const std::string label = std::to_string(m.labels.size() == nt ? m.labels(t) : 0);
    out += std::to_string(t + 1) + " 4 2 " + label + " " + label;
    for (int k = 0; k < 4; ++k) out += " " + std::to_string(m.tets(t, k) + 1);
    out += '\n';
  }
  out += "$EndElements\n";
  write_file_atomic(path, out);
}

}  // namespace softcut::mesh::io
