#include "sim/vtu_export.hpp"

#include <cstdio>

#include "core/atomic_file.hpp"

namespace softcut::sim {

namespace fs = std::filesystem;

std::uintmax_t write_vtu(const fs::path& path, const Model& m, const State& s) {
  const mesh::TetMesh& mesh = current_mesh(m, s);
  const Eigen::MatrixX3d& u = s.displacement;
  const std::vector<char>& operational = s.cut ? s.cut->operational_tet : m.partition.operational_tet;
  return write_file_atomic(path, [&](std::ostream& os) {
    char buf[128];
    os << "<?xml version=\"1.0\"?>\n<VTKFile type=\"UnstructuredGrid\" version=\"0.1\" byte_order=\"LittleEndian\">\n"
       << "  <UnstructuredGrid>\n    <Piece NumberOfPoints=\"" << mesh.num_nodes() << "\" NumberOfCells=\""
       << mesh.num_tets() << "\">\n";
    os << "      <Points>\n        <DataArray type=\"Float64\" NumberOfComponents=\"3\" format=\"ascii\">\n";
    for (int n = 0; n < mesh.num_nodes(); ++n) {
      std::snprintf(buf, sizeof buf, "%.9e %.9e %.9e\n", mesh.nodes(n, 0), mesh.nodes(n, 1), mesh.nodes(n, 2));
      os << buf;
    }
    os << "        </DataArray>\n      </Points>\n      <PointData Vectors=\"displacement\">\n"
       << "        <DataArray type=\"Float64\" Name=\"displacement\" NumberOfComponents=\"3\" format=\"ascii\">\n";
    for (int n = 0; n < mesh.num_nodes(); ++n) {
      std::snprintf(buf, sizeof buf, "%.9e %.9e %.9e\n", u(n, 0), u(n, 1), u(n, 2));
      os << buf;
    }
    os << "        </DataArray>\n        <DataArray type=\"Int32\" Name=\"node_set\" format=\"ascii\">\n";
    for (int n = 0; n < mesh.num_nodes(); ++n) os << int(node_set(m, s, n)) << '\n';
    os << "        </DataArray>\n      </PointData>\n      <CellData Scalars=\"label\">\n"
       << "        <DataArray type=\"Int32\" Name=\"label\" format=\"ascii\">\n";
    for (int t = 0; t < mesh.num_tets(); ++t) os << mesh.labels(t) << '\n';
    os << "        </DataArray>\n        <DataArray type=\"Int32\" Name=\"operational\" format=\"ascii\">\n";
    for (int t = 0; t < mesh.num_tets(); ++t) os << int(operational[size_t(t)]) << '\n';
    os << "        </DataArray>\n      </CellData>\n      <Cells>\n"
       << "        <DataArray type=\"Int32\" Name=\"connectivity\" format=\"ascii\">\n";
    for (int t = 0; t < mesh.num_tets(); ++t)
      os << mesh.tets(t, 0) << ' ' << mesh.tets(t, 1) << ' ' << mesh.tets(t, 2) << ' ' << mesh.tets(t, 3) << '\n';
    os << "        </DataArray>\n        <DataArray type=\"Int32\" Name=\"offsets\" format=\"ascii\">\n";
    for (int t = 0; t < mesh.num_tets(); ++t) os << 4 * (t + 1) << '\n';
    os << "        </DataArray>\n        <DataArray type=\"UInt8\" Name=\"types\" format=\"ascii\">\n";
    for (int t = 0; t < mesh.num_tets(); ++t) os << "10\n";
    os << "        </DataArray>\n      </Cells>\n    </Piece>\n  </UnstructuredGrid>\n</VTKFile>\n";
  });
}

}  // namespace softcut::sim
