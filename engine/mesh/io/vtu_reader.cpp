// VTK XML unstructured grid reader (.vtu). DataArrays may be ascii, inline
// base64 binary (header UInt32 or UInt64, optionally zlib-compressed with
// vtkZLibDataCompressor) or appended (raw or base64). Cells of type 10 are
// kept; a one-component CellData array named like a label gives the labels.
// The XML is parsed by pugixml (entities, CDATA, comments as any XML reader
// takes them); appended data after its '_' marker is raw bytes, not XML, so
// only the text before it is parsed.
#include <pugixml.hpp>
#include <zlib.h>

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdint>
#include <cstring>

#include "mesh/io/base64.hpp"
#include "mesh/io/formats.hpp"
#include "mesh/io/text_reader.hpp"

namespace softcut::mesh::io {

// Floating-point values are copied byte-wise from little-endian data.
static_assert(std::endian::native == std::endian::little, "mesh readers assume a little-endian host");

namespace {

struct ArrayRef {
  std::string name, type, format;
  std::int64_t ncomp = 1, offset = -1;
  std::string_view content;     // inline content (into the parsed XML, or `joined`)
  std::string joined;           // content split by comments or CDATA, joined
  std::size_t at = 0;           // file offset of the tag
  std::size_t content_at = 0;   // file offset of the content
  std::string_view text() const { return joined.empty() ? content : std::string_view(joined); }
};

int type_size(const std::string& t) {
  if (t == "Int8" || t == "UInt8") return 1;
  if (t == "Int16" || t == "UInt16") return 2;
  if (t == "Int32" || t == "UInt32" || t == "Float32") return 4;
  if (t == "Int64" || t == "UInt64" || t == "Float64") return 8;
  return 0;
}

class VtuFile {
 public:
  VtuFile(const std::string& source, std::string_view text, std::size_t max_bytes)
      : source_(source), text_(text), max_bytes_(max_bytes) {}

  TetMesh read(Diagnostics& diag);

 private:
  int line_at(std::size_t off) const {
    int line = 1;
    for (std::size_t i = 0; i < off && i < text_.size(); ++i) line += text_[i] == '\n';
    return line;
  }
  template <class... Args>
  [[noreturn]] void fail_at(std::size_t off, const Args&... args) const {
    fail(source_, ":", line_at(off), ": ", args...);
  }
  template <class... Args>
  [[noreturn]] void fail_array(const ArrayRef& a, const Args&... args) const {
    fail(source_, ":", line_at(a.at), ": DataArray '", a.name, "': ", args...);
  }

  void scan();
  bool self_closing(std::size_t name_at) const;
  std::size_t appended_tag() const;
  void collect(const pugi::xml_node& node, std::string_view section, int depth);
  std::int64_t int_attr(const pugi::xml_node& t, const char* key, bool required);
  std::size_t offset_of(const pugi::xml_node& n) const { return std::size_t(std::max<std::ptrdiff_t>(0, n.offset_debug())); }
  // `need`: the bytes the array must hold, checked before anything is inflated.
  std::string block_bytes(const ArrayRef& a, std::string_view bytes, std::uint64_t need) const;
  std::uint64_t header_value(std::string_view bytes, std::size_t i) const;
  std::vector<double> decode(const ArrayRef& a, std::int64_t expected) const;

  std::string source_;
  std::string_view text_;
  std::size_t max_bytes_;  // the most one decoded array may take (ReadOptions::max_bytes)
  std::string xml_;        // the XML part of the file, parsed in place by pugixml
  pugi::xml_document doc_;
  bool big_endian_ = false, compressed_ = false;
  int header_size_ = 4;
  std::int64_t npoints_ = -1, ncells_ = -1;
  std::vector<ArrayRef> points_, cells_, cell_data_;
  std::string appended_encoding_;
  std::size_t appended_begin_ = 0, appended_end_ = 0;
  bool have_appended_ = false, have_piece_ = false;
  std::vector<std::int64_t> appended_offsets_;  // sorted, for base64 chunk ends
};

std::int64_t VtuFile::int_attr(const pugi::xml_node& t, const char* key, bool required) {
  const std::string_view v = t.attribute(key).value();
  if (v.empty()) {
    if (required) fail_at(offset_of(t), "<", t.name(), "> has no ", key, " attribute");
    return -1;
  }
  std::int64_t out;
  if (!parse_int(v, out) || out < 0) fail_at(offset_of(t), key, "=\"", v, "\" of <", t.name(), "> is not a count");
  return out;
}

// Depth first, as the file reads: DataArrays belong to the nearest enclosing
// Points, Cells or CellData (those in PointData and FieldData are not needed).
void VtuFile::collect(const pugi::xml_node& node, std::string_view section, int depth) {
  // VTU is a few levels deep; a file nested past this is refused, not recursed into.
  if (depth > 64) fail_at(offset_of(node), "XML elements nested more than 64 deep; not a VTU grid");
  for (const pugi::xml_node& c : node.children()) {
    if (c.type() != pugi::node_element) continue;
    const std::string_view name = c.name();
    if (name == "Piece") {
      if (have_piece_) fail_at(offset_of(c), "more than one <Piece>; merge the pieces into one grid before loading");
      have_piece_ = true;
      npoints_ = int_attr(c, "NumberOfPoints", true);
      ncells_ = int_attr(c, "NumberOfCells", true);
      if (npoints_ > INT32_MAX || ncells_ > INT32_MAX) fail_at(offset_of(c), "too many points or cells");
      collect(c, section, depth + 1);
    } else if (name == "Points" || name == "Cells" || name == "CellData" || name == "PointData" ||
               name == "FieldData") {
      collect(c, name, depth + 1);
    } else if (name == "DataArray") {
      ArrayRef a;
      a.name = c.attribute("Name").value();
      a.type = c.attribute("type").value();
      a.format = c.attribute("format").value();
      a.at = offset_of(c);
      const std::int64_t nc = int_attr(c, "NumberOfComponents", false);
      a.ncomp = nc < 0 ? 1 : nc;
      if (a.format == "appended") {
        a.offset = int_attr(c, "offset", true);
        appended_offsets_.push_back(a.offset);
      }
      // The text children (one, unless comments or CDATA split it).
      int parts = 0;
      for (const pugi::xml_node& t : c.children())
        if (t.type() == pugi::node_pcdata || t.type() == pugi::node_cdata) {
          const std::string_view v = t.value();
          if (parts++ == 0) {
            a.content = v;
            a.content_at = v.data() >= xml_.data() && v.data() <= xml_.data() + xml_.size()
                               ? std::size_t(v.data() - xml_.data()) : a.at;
          } else {
            if (parts == 2) a.joined = a.content;
            a.joined += ' ';
            a.joined += v;
          }
        }
      if (a.content_at == 0) a.content_at = a.at;
      if (section == "Points") points_.push_back(std::move(a));
      else if (section == "Cells") cells_.push_back(std::move(a));
      else if (section == "CellData") cell_data_.push_back(std::move(a));
    } else if (name == "AppendedData") {
      have_appended_ = true;
      appended_encoding_ = c.attribute("encoding").value();
      if (appended_encoding_ != "raw" && appended_encoding_ != "base64")
        fail_at(offset_of(c), "AppendedData encoding '", appended_encoding_, "' is not supported (raw or base64)");
    } else {
      collect(c, section, depth + 1);
    }
  }
}

// Whether the start tag whose name begins at `name_at` ends in "/>" (quoted
// attribute values may hold '>').
bool VtuFile::self_closing(std::size_t name_at) const {
  char quote = 0;
  for (std::size_t i = name_at; i < text_.size(); ++i) {
    const char c = text_[i];
    if (quote) {
      if (c == quote) quote = 0;
    } else if (c == '"' || c == '\'') {
      quote = c;
    } else if (c == '>') {
      return i > name_at && text_[i - 1] == '/';
    }
  }
  return false;
}

// Offset of the <AppendedData tag: the first one outside comments and CDATA
// sections; npos when there is none.
std::size_t VtuFile::appended_tag() const {
  for (std::size_t from = 0;;) {
    const std::size_t app = text_.find("<AppendedData", from);
    if (app == std::string_view::npos) return app;
    // Past the end of a comment or CDATA section that holds it (linear: each
    // section is skipped once); an unterminated one holds the rest of the file.
    std::size_t past = app;
    for (const auto& [open, close] : {std::pair<std::string_view, std::string_view>{"<!--", "-->"}, {"<![CDATA[", "]]>"}}) {
      const std::size_t o = text_.rfind(open, app);
      if (o == std::string_view::npos) continue;
      const std::size_t c = text_.find(close, o + open.size());
      if (c == std::string_view::npos) return std::string_view::npos;
      if (c > app) past = std::max(past, c + close.size());
    }
    if (past == app) return app;
    from = past;
  }
}

void VtuFile::scan() {
  // The XML part ends with the <AppendedData ...> tag, when there is one:
  // its data starts after a '_' and is not XML.
  std::size_t xml_end = text_.size(), tag_end = std::string_view::npos;
  if (const std::size_t app = appended_tag(); app != std::string_view::npos) {
    tag_end = text_.find('>', app);
    if (tag_end == std::string_view::npos) fail_at(app, "file ends inside an XML tag");
    xml_end = tag_end + 1;
  }
  xml_.assign(text_.substr(0, xml_end));
  const pugi::xml_parse_result r =
      doc_.load_buffer_inplace(xml_.data(), xml_.size(), pugi::parse_default, pugi::encoding_utf8);
  // The innermost element that was open when the text ended.
  pugi::xml_node last = doc_;
  while (last.last_child() && last.last_child().type() == pugi::node_element) last = last.last_child();
  const std::size_t at = std::size_t(std::max<std::ptrdiff_t>(0, r.offset));
  if (r.status == pugi::status_end_element_mismatch && at + 1 >= xml_.size()) {
    // Elements left open at the end: the file is cut short, or its XML part
    // ends at <AppendedData> (by design). A cut inside a DataArray is named.
    if (std::string_view(last.name()) == "DataArray" && !self_closing(offset_of(last)) &&
        text_.find("</DataArray", offset_of(last)) == std::string_view::npos)
      fail_at(offset_of(last), "DataArray '", last.attribute("Name").value(), "' has no </DataArray>");
  } else if (r.status == pugi::status_end_element_mismatch) {
    fail_at(at, "malformed XML: an end tag does not match the innermost open element, <", last.name(), "> (line ",
            line_at(offset_of(last)), ")");
  } else if (r.status == pugi::status_bad_attribute) {
    fail_at(at, "an attribute of <", last.name(), "> is malformed: its value is not quoted, or its '=' is missing");
  } else if (r.status == pugi::status_no_document_element) {
    fail(source_, ": not a VTK XML file (no <VTKFile> element)");
  } else if (r.status != pugi::status_ok) {
    fail_at(at, "malformed XML: ", r.description());
  }
  const pugi::xml_node file = doc_.document_element();
  if (std::string_view(file.name()) != "VTKFile") fail(source_, ": not a VTK XML file (no <VTKFile> element)");
  const std::string_view type = file.attribute("type").value();
  if (type != "UnstructuredGrid")
    fail_at(offset_of(file), "VTK XML type '", type, "' is not supported; expected UnstructuredGrid");
  const std::string_view order = file.attribute("byte_order").value(), header = file.attribute("header_type").value();
  const std::string_view comp = file.attribute("compressor").value();
  if (order == "BigEndian") big_endian_ = true;
  else if (!order.empty() && order != "LittleEndian") fail_at(offset_of(file), "unknown byte_order '", order, "'");
  if (header == "UInt64") header_size_ = 8;
  else if (!header.empty() && header != "UInt32") fail_at(offset_of(file), "unknown header_type '", header, "'");
  if (comp == "vtkZLibDataCompressor") compressed_ = true;
  else if (!comp.empty())
    fail_at(offset_of(file), "compressor '", comp, "' is not supported; save uncompressed or with zlib compression");
  collect(file, "", 0);
  if (!have_piece_) fail(source_, ": no <Piece> element; the grid is empty or the file is truncated");
  if (have_appended_) {
    const std::size_t underscore = text_.find('_', tag_end);
    if (underscore == std::string_view::npos) fail_at(tag_end, "AppendedData has no '_' marking its start");
    appended_begin_ = underscore + 1;
    const std::size_t close = text_.rfind("</AppendedData>");
    appended_end_ = close == std::string_view::npos || close < appended_begin_ ? text_.size() : close;
  }
  std::sort(appended_offsets_.begin(), appended_offsets_.end());
}

std::uint64_t VtuFile::header_value(std::string_view bytes, std::size_t i) const {
  unsigned char b[8] = {};
  std::memcpy(b, bytes.data() + i * std::size_t(header_size_), std::size_t(header_size_));
  if (big_endian_) std::reverse(b, b + header_size_);
  std::uint64_t v = 0;
  for (int k = header_size_ - 1; k >= 0; --k) v = v << 8 | b[k];
  return v;
}

// Header plus data of one binary block -> the (decompressed) data bytes.
std::string VtuFile::block_bytes(const ArrayRef& a, std::string_view bytes, std::uint64_t need) const {
  const std::size_t hs = std::size_t(header_size_);
  if (!compressed_) {
    if (bytes.size() < hs) fail_array(a, "binary block ends inside its header");
    const std::uint64_t n = header_value(bytes, 0);
    if (n > bytes.size() - hs) fail_array(a, "header announces ", n, " bytes but only ", bytes.size() - hs, " follow");
    return std::string(bytes.substr(hs, std::size_t(n)));
  }
  if (bytes.size() < 3 * hs) fail_array(a, "compressed block ends inside its header");
  const std::uint64_t nb = header_value(bytes, 0), bs = header_value(bytes, 1), last = header_value(bytes, 2);
  if (nb > bytes.size() / hs - 3) fail_array(a, "compressed header announces ", nb, " blocks; the data is too short");
  const std::size_t data0 = (3 + std::size_t(nb)) * hs;
  // Summed with a per-block check, so 64-bit sizes cannot wrap the total.
  std::uint64_t csum = 0;
  for (std::size_t b = 0; b < nb; ++b) {
    const std::uint64_t csize = header_value(bytes, 3 + b);
    if (csize > bytes.size() - data0 - csum)
      fail_array(a, "compressed block ", b, " needs ", csize, " bytes but only ", bytes.size() - data0 - csum,
                 " follow");
    csum += csize;
  }
  // zlib expands at most ~1032:1, which bounds what a header may ask for.
  const std::uint64_t total = nb == 0 ? 0 : (nb - 1) * bs + (last == 0 ? bs : last);
  if (bs > 1032 * (csum + 64) || total > 1032 * (csum + 64))
    fail_array(a, "compressed header announces ", total, " bytes, more than ", csum, " compressed bytes can hold");
  if (total != need) fail_array(a, "compressed header announces ", total, " bytes; the array needs ", need);
  std::string out(std::size_t(total), '\0');
  std::size_t in = data0, at = 0;
  for (std::size_t b = 0; b < nb; ++b) {
    const std::uint64_t csize = header_value(bytes, 3 + b);
    const uLongf want = uLongf(b + 1 == nb && last != 0 ? last : bs);
    if (want > out.size() - at) fail_array(a, "compressed header block sizes do not add up to ", total, " bytes");
    uLongf got = want;
    const int rc = uncompress(reinterpret_cast<Bytef*>(out.data() + at), &got,
                              reinterpret_cast<const Bytef*>(bytes.data() + in), uLong(csize));
    if (rc != Z_OK || got != want) fail_array(a, "zlib block ", b, " does not decompress to ", want, " bytes (zlib code ", rc, ")");
    in += std::size_t(csize);
    at += std::size_t(want);
  }
  return out;
}

std::vector<double> VtuFile::decode(const ArrayRef& a, std::int64_t expected) const {
  const int size = type_size(a.type);
  if (size == 0) fail_array(a, "data type '", a.type, "' is not supported");
  std::vector<double> out;
  if (a.format == "ascii") {
    TextReader r(source_, a.text(), line_at(a.content_at));
    out.reserve(reserve_cap(expected, a.text().size(), 2));
    std::string_view tok;
    while (r.next_token(tok)) {
      if (std::int64_t(out.size()) >= expected)
        r.fail_here("DataArray '", a.name, "' holds more than the ", expected, " values expected");
      out.push_back(r.to_double_lazy(tok, [&] { return cat("a value of DataArray '", a.name, "'"); }));
    }
    if (std::int64_t(out.size()) != expected) fail_array(a, "expected ", expected, " values, found ", out.size());
    return out;
  }
  // Binary data: what it decodes to is bounded before it is allocated.
  const std::uint64_t need = std::uint64_t(expected) * std::uint64_t(size);
  if (a.format != "ascii" && (expected < 0 || need / std::uint64_t(size) != std::uint64_t(expected) ||
                              need + std::uint64_t(expected) * sizeof(double) > max_bytes_))
    fail_array(a, expected, " values of type ", a.type, " would take ", need + std::uint64_t(expected) * sizeof(double),
               " bytes decoded, more than the ", max_bytes_, " bytes allowed (the memory budget: a sandboxed run's, which "
               "--trust lifts, or softcut mesh --max-memory)");
  std::string data;
  if (a.format == "binary") {
    std::size_t bad = 0;
    auto bytes = base64_decode(a.text(), &bad);
    if (!bytes) fail_at(a.content_at + (a.joined.empty() ? bad : 0), "DataArray '", a.name, "': invalid base64 data");
    data = block_bytes(a, *bytes, need);
  } else if (a.format == "appended") {
    if (!have_appended_) fail_array(a, "format=\"appended\" but the file has no <AppendedData>");
    const std::size_t len = appended_end_ - appended_begin_;
    if (std::uint64_t(a.offset) > len) fail_array(a, "offset ", a.offset, " lies beyond the appended data (", len, " bytes)");
    const std::size_t from = appended_begin_ + std::size_t(a.offset);
    if (appended_encoding_ == "raw") {
      data = block_bytes(a, text_.substr(from, appended_end_ - from), need);
    } else {
      auto next = std::upper_bound(appended_offsets_.begin(), appended_offsets_.end(), a.offset);
      const std::size_t to = next == appended_offsets_.end() ? appended_end_
                                                             : std::min(appended_end_, appended_begin_ + std::size_t(*next));
      std::size_t bad = 0;
      auto bytes = base64_decode(text_.substr(from, to - from), &bad);
      if (!bytes) fail_at(from + bad, "DataArray '", a.name, "': invalid base64 appended data");
      data = block_bytes(a, *bytes, need);
    }
  } else {
    fail_array(a, "format '", a.format, "' is not supported (ascii, binary or appended)");
  }
  if (data.size() != std::size_t(expected) * std::size_t(size))
    fail_array(a, "expected ", expected, " values of type ", a.type, " (", std::size_t(expected) * std::size_t(size),
               " bytes), found ", data.size(), " bytes");
  out.resize(std::size_t(expected));
  const bool is_float = a.type[0] == 'F', is_unsigned = a.type[0] == 'U';
  for (std::size_t i = 0; i < out.size(); ++i) {
    unsigned char b[8];  // little-endian after the swap
    std::memcpy(b, data.data() + i * std::size_t(size), std::size_t(size));
    if (big_endian_) std::reverse(b, b + size);
    if (is_float) {
      if (size == 4) { float f; std::memcpy(&f, b, 4); out[i] = f; }
      else { double d; std::memcpy(&d, b, 8); out[i] = d; }
    } else {
      std::uint64_t u = 0;
      for (int k = size - 1; k >= 0; --k) u = u << 8 | b[k];
      const int shift = 64 - 8 * size;
      out[i] = is_unsigned ? double(u) : double(std::int64_t(u << shift) >> shift);
    }
  }
  return out;
}

TetMesh VtuFile::read(Diagnostics& diag) {
  scan();
  auto find = [&](const std::vector<ArrayRef>& v, std::string_view name, std::string_view what) -> const ArrayRef& {
    for (const auto& a : v)
      if (name.empty() || a.name == name) return a;
    fail(source_, ": no ", what, " DataArray found");
  };
  const ArrayRef& pa = find(points_, "", "<Points>");
  if (pa.ncomp != 3) fail_array(pa, "points need 3 components, found ", pa.ncomp);
  MeshBuffers buf;
  buf.xyz = decode(pa, 3 * npoints_);
  for (std::size_t i = 0; i < buf.xyz.size(); ++i)
    if (!std::isfinite(buf.xyz[i]))
      fail_array(pa, "point ", i / 3, " has a non-finite coordinate (", buf.xyz[i], "); fix or remove that node");
  const ArrayRef& oa = find(cells_, "offsets", "Cells 'offsets'");
  const ArrayRef& ta = find(cells_, "types", "Cells 'types'");
  const ArrayRef& ca = find(cells_, "connectivity", "Cells 'connectivity'");
  const std::vector<double> offsets = decode(oa, ncells_), types = decode(ta, ncells_);
  double prev = 0;
  for (std::size_t c = 0; c < offsets.size(); ++c) {
    if (!(offsets[c] >= prev && offsets[c] == std::floor(offsets[c]) && offsets[c] <= double(INT32_MAX) * 8))
      fail_array(oa, "offset of cell ", c, " (", offsets[c], ") is not an integer >= the previous offset ", prev);
    prev = offsets[c];
  }
  const std::vector<double> conn = decode(ca, std::int64_t(prev));
  std::vector<double> labels;
  const ArrayRef* la = nullptr;
  for (const auto& a : cell_data_)
    if (a.ncomp == 1 && label_name_rank(a.name) >= 0 && (!la || label_name_rank(a.name) < label_name_rank(la->name)))
      la = &a;
  if (la) {
    labels = decode(*la, ncells_);
    for (std::size_t c = 0; c < labels.size(); ++c)
      if (!label_value_ok(labels[c])) fail_array(*la, "label ", labels[c], " of cell ", c, " is not an integer");
  }
  SkippedElements skipped;
  std::size_t begin = 0;
  for (std::size_t c = 0; c < offsets.size(); ++c) {
    const std::size_t end = std::size_t(offsets[c]);
    if (!label_value_ok(types[c])) fail_array(ta, "type ", types[c], " of cell ", c, " is not an integer");
    const int type = int(types[c]);
    if (type != 10) {
      skipped.add(type == 5 ? "triangle" : type == 3 ? "line" : type == 1 ? "vertex" : type == 12 ? "hexahedron" : cat("cell type ", type));
    } else {
      if (end - begin != 4) fail_array(oa, "cell ", c, " is a tetrahedron (type 10) with ", end - begin, " points; expected 4");
      for (std::size_t k = begin; k < end; ++k) {
        const double v = conn[k];
        if (!(v >= 0 && v < double(npoints_) && v == std::floor(v)))
          fail_array(ca, "cell ", c, " refers to point ", v, ", but the file has points 0..", npoints_ - 1);
        buf.tet.push_back(int(v));
      }
      buf.label.push_back(la ? int(labels[c]) : 0);
    }
    begin = end;
  }
  skipped.report(source_, diag);
  return buf.finish();
}

}  // namespace

TetMesh read_vtu(const std::string& source, std::string_view text, Diagnostics& diag, std::size_t max_bytes) {
  VtuFile f(source, text, max_bytes);
  return f.read(diag);
}

}  // namespace softcut::mesh::io
