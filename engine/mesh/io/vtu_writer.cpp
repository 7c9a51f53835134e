// VTK XML unstructured grid writer: the XML by pugixml, the arrays appended
// raw after it (each block: its byte count as UInt64, then the values).
#include "mesh/io/vtu_writer.hpp"

#include <pugixml.hpp>

#include <bit>
#include <cstring>

#include "core/atomic_file.hpp"
#include "core/error.hpp"

namespace softcut::mesh::io {

static_assert(std::endian::native == std::endian::little, "the VTU writer writes little-endian data");

namespace {

// The appended section being built: each array's block and its offset.
struct Appended {
  std::string bytes;

  template <class T>
  std::uint64_t add(const T* v, std::size_t n) {
    const std::uint64_t offset = bytes.size();
    const std::uint64_t size = n * sizeof(T);
    bytes.append(reinterpret_cast<const char*>(&size), sizeof size);
    if (size) bytes.append(reinterpret_cast<const char*>(v), size);
    return offset;
  }
};

void data_array(pugi::xml_node parent, const char* type, const std::string& name, int components,
                std::uint64_t offset) {
  pugi::xml_node a = parent.append_child("DataArray");
  a.append_attribute("type") = type;
  a.append_attribute("Name") = name.c_str();
  if (components > 1) a.append_attribute("NumberOfComponents") = components;
  a.append_attribute("format") = "appended";
  a.append_attribute("offset") = static_cast<unsigned long long>(offset);
}

void add_array(pugi::xml_node parent, Appended& app, const VtuArray& a, std::size_t rows, const char* where) {
  if (a.components < 1) fail("VTU ", where, " array '", a.name, "': ", a.components, " components (need >= 1)");
  const std::size_t want = rows * std::size_t(a.components);
  const std::size_t have = a.type == VtuArray::Type::float64 ? a.f64.size() : a.i32.size();
  if (have != want)
    fail("VTU ", where, " array '", a.name, "' has ", have, " values; the mesh needs ", rows, " x ", a.components);
  if (a.type == VtuArray::Type::float64) data_array(parent, "Float64", a.name, a.components, app.add(a.f64.data(), want));
  else data_array(parent, "Int32", a.name, a.components, app.add(a.i32.data(), want));
}

struct StringWriter : pugi::xml_writer {
  std::string out;
  void write(const void* data, size_t size) override { out.append(static_cast<const char*>(data), size); }
};

}  // namespace

std::uintmax_t write_vtu(const std::filesystem::path& path, const TetMesh& m, const VtuFields& fields) {
  const int nn = m.num_nodes(), nt = m.num_tets();
  Appended app;
  pugi::xml_document doc;
  pugi::xml_node decl = doc.append_child(pugi::node_declaration);
  decl.append_attribute("version") = "1.0";
  pugi::xml_node vtk = doc.append_child("VTKFile");
  vtk.append_attribute("type") = "UnstructuredGrid";
  vtk.append_attribute("version") = "1.0";
  vtk.append_attribute("byte_order") = "LittleEndian";
  vtk.append_attribute("header_type") = "UInt64";
  pugi::xml_node piece = vtk.append_child("UnstructuredGrid").append_child("Piece");
  piece.append_attribute("NumberOfPoints") = nn;
  piece.append_attribute("NumberOfCells") = nt;

  std::vector<double> xyz(std::size_t(3) * std::size_t(nn));
  for (int i = 0; i < nn; ++i)
    for (int c = 0; c < 3; ++c) xyz[std::size_t(3 * i + c)] = m.nodes(i, c);
  data_array(piece.append_child("Points"), "Float64", "Points", 3, app.add(xyz.data(), xyz.size()));

  std::vector<std::int64_t> conn(std::size_t(4) * std::size_t(nt));
  std::vector<std::int64_t> offsets(static_cast<std::size_t>(nt));
  std::vector<std::uint8_t> types(std::size_t(nt), 10);  // VTK_TETRA
  for (int t = 0; t < nt; ++t) {
    for (int k = 0; k < 4; ++k) conn[std::size_t(4 * t + k)] = m.tets(t, k);
    offsets[std::size_t(t)] = 4 * std::int64_t(t + 1);
  }
  pugi::xml_node cells = piece.append_child("Cells");
  data_array(cells, "Int64", "connectivity", 1, app.add(conn.data(), conn.size()));
  data_array(cells, "Int64", "offsets", 1, app.add(offsets.data(), offsets.size()));
  data_array(cells, "UInt8", "types", 1, app.add(types.data(), types.size()));

  if (!fields.point_data.empty()) {
    pugi::xml_node pd = piece.append_child("PointData");
    if (!fields.point_vectors.empty()) pd.append_attribute("Vectors") = fields.point_vectors.c_str();
    for (const VtuArray& a : fields.point_data) add_array(pd, app, a, std::size_t(nn), "point data");
  }
  pugi::xml_node cd = piece.append_child("CellData");
  cd.append_attribute("Scalars") = "label";
  std::vector<std::int32_t> labels(std::size_t(nt), 0);
  if (m.labels.size() == nt)
    for (int t = 0; t < nt; ++t) labels[std::size_t(t)] = m.labels(t);
  data_array(cd, "Int32", "label", 1, app.add(labels.data(), labels.size()));
  for (const VtuArray& a : fields.cell_data) add_array(cd, app, a, std::size_t(nt), "cell data");

  pugi::xml_node data = vtk.append_child("AppendedData");
  data.append_attribute("encoding") = "raw";
  data.append_child(pugi::node_pcdata).set_value("_");  // the marker; the raw bytes follow it
  StringWriter xml;
  doc.save(xml, "  ", pugi::format_indent, pugi::encoding_utf8);
  const std::string marker = ">_</AppendedData>";
  const std::size_t at = xml.out.rfind(marker);
  if (at == std::string::npos) fail("VTU writer: pugixml did not write the appended-data marker");
  const std::size_t split = at + 2;  // after "_"
  return write_file_atomic(path, [&](std::ostream& os) {
    os.write(xml.out.data(), std::streamsize(split));
    os.write(app.bytes.data(), std::streamsize(app.bytes.size()));
    os << "\n  ";  // as VTK writes it: readers that find the data's end by the last line break (meshio) need it
    os.write(xml.out.data() + split, std::streamsize(xml.out.size() - split));
  }, true);
}

}  // namespace softcut::mesh::io
