// VTK XML unstructured grid writer: inline base64 binary arrays (header
// UInt64 encoded together with the data, uncompressed), so doubles round-trip
// bit for bit. Labels go to CellData "label".
#include <bit>
#include <cstdint>
#include <cstring>

#include "core/atomic_file.hpp"
#include "mesh/io/base64.hpp"
#include "mesh/io/formats.hpp"

namespace softcut::mesh::io {

namespace {

// Header (byte count, UInt64) followed by the raw values, as one base64 stream.
template <class T>
std::string encode(const std::vector<T>& v) {
  const std::uint64_t n = v.size() * sizeof(T);
  std::string bytes(sizeof(n) + n, '\0');
  std::memcpy(bytes.data(), &n, sizeof(n));
  if (n) std::memcpy(bytes.data() + sizeof(n), v.data(), n);
  return base64_encode(bytes);
}

void data_array(std::ostream& os, const char* type, const char* name, int ncomp, const std::string& base64) {
  os << "        <DataArray type=\"" << type << "\" Name=\"" << name << "\"";
  if (ncomp > 1) os << " NumberOfComponents=\"" << ncomp << "\"";
  os << " format=\"binary\">\n          " << base64 << "\n        </DataArray>\n";
}

}  // namespace

void write_vtu(const std::filesystem::path& path, const TetMesh& m) {
  const int nn = m.num_nodes(), nt = m.num_tets();
  std::vector<double> xyz(std::size_t(3) * std::size_t(nn));
  for (int i = 0; i < nn; ++i)
    for (int c = 0; c < 3; ++c) xyz[std::size_t(3 * i + c)] = m.nodes(i, c);
  std::vector<std::int64_t> conn(std::size_t(4) * std::size_t(nt));
  std::vector<std::int64_t> offsets(std::size_t(nt), 0);
  std::vector<std::uint8_t> types(std::size_t(nt), 10);
  std::vector<std::int32_t> labels(std::size_t(nt), 0);
  for (int t = 0; t < nt; ++t) {
    for (int k = 0; k < 4; ++k) conn[std::size_t(4 * t + k)] = m.tets(t, k);
    offsets[std::size_t(t)] = 4 * std::int64_t(t + 1);
    if (m.labels.size() == nt) labels[std::size_t(t)] = m.labels(t);
  }
  const char* order = std::endian::native == std::endian::little ? "LittleEndian" : "BigEndian";
  write_file_atomic(path, [&](std::ostream& os) {
    os << "<?xml version=\"1.0\"?>\n"
       << "<VTKFile type=\"UnstructuredGrid\" version=\"1.0\" byte_order=\"" << order << "\" header_type=\"UInt64\">\n"
       << "  <UnstructuredGrid>\n"
       << "    <Piece NumberOfPoints=\"" << nn << "\" NumberOfCells=\"" << nt << "\">\n"
       << "      <Points>\n";
    data_array(os, "Float64", "Points", 3, encode(xyz));
    os << "      </Points>\n      <Cells>\n";
    data_array(os, "Int64", "connectivity", 1, encode(conn));
    data_array(os, "Int64", "offsets", 1, encode(offsets));
    data_array(os, "UInt8", "types", 1, encode(types));
    os << "      </Cells>\n      <CellData Scalars=\"label\">\n";
    data_array(os, "Int32", "label", 1, encode(labels));
    os << "      </CellData>\n    </Piece>\n  </UnstructuredGrid>\n</VTKFile>\n";
  }, true);
}

}  // namespace softcut::mesh::io
