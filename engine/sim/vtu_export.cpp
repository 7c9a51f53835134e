#include "sim/vtu_export.hpp"

#include "mesh/io/vtu_writer.hpp"

namespace softcut::sim {

std::uintmax_t write_vtu(const std::filesystem::path& path, const Model& m, const State& s) {
  const mesh::TetMesh& mesh = current_mesh(m, s);
  const std::vector<char>& operational = s.cut ? s.cut->operational_tet : m.partition.operational_tet;
  const int nn = mesh.num_nodes(), nt = mesh.num_tets();
  using A = mesh::io::VtuArray;
  A u{"displacement", A::Type::float64, 3, {}, {}};
  A sets{"node_set", A::Type::int32, 1, {}, {}};
  A op{"operational", A::Type::int32, 1, {}, {}};
  A group{"material", A::Type::int32, 1, {}, {}};
  u.f64.reserve(std::size_t(3) * std::size_t(nn));
  for (int n = 0; n < nn; ++n) {
    for (int c = 0; c < 3; ++c) u.f64.push_back(s.displacement(n, c));
    sets.i32.push_back(int(node_set(m, s, n)));
  }
  for (int t = 0; t < nt; ++t) {
    op.i32.push_back(operational[std::size_t(t)]);
    group.i32.push_back(m.tet_group[std::size_t(s.cut ? s.cut->origin_tet[std::size_t(t)] : t)]);
  }
  mesh::io::VtuFields fields;
  fields.point_data = {std::move(u), std::move(sets)};
  fields.point_vectors = "displacement";
  fields.cell_data = {std::move(op), std::move(group)};
  return mesh::io::write_vtu(path, mesh, fields);
}

}  // namespace softcut::sim
