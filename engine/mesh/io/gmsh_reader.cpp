// Gmsh .msh ASCII reader: format versions 1 ($NOD/$ELM), 2.x and 4.1.
// Node tags may be any positive integers in any order; a node's id is its
// position in the file. Only 4-node tetrahedra (type 4) are kept.
#include <algorithm>
#include <cctype>
#include <cstdint>
#include <string>
#include <unordered_map>

#include "mesh/io/formats.hpp"
#include "mesh/io/text_reader.hpp"

namespace softcut::mesh::io {

namespace {

// Nodes per element type (Gmsh element type ids), -1 where unknown here.
int gmsh_nodes_per_element(std::int64_t type) {
  static const int kNodes[] = {-1, 2,  3,  4,  4,  8,  6,  5,  3,  6,  9,  10, 27, 18, 14, 1,
                               8,  20, 15, 13, 9,  10, 12, 15, 15, 21, 4,  5,  6,  20, 35, 56};
  return type >= 0 && type < std::int64_t(std::size(kNodes)) ? kNodes[type] : -1;
}

std::string gmsh_type_name(std::int64_t type) {
  switch (type) {
    case 1: return "line";
    case 2: return "triangle";
    case 3: return "quadrangle";
    case 4: return "tetrahedron";
    case 5: return "hexahedron";
    case 6: return "prism";
    case 7: return "pyramid";
    case 8: return "second-order line";
    case 9: return "second-order triangle";
    case 11: return "second-order tetrahedron";
    case 15: return "point";
    default: return cat("element type ", type);
  }
}

constexpr std::int64_t kTet = 4;

struct GmshFile {
  TextReader r;
  int version = 0;  // 1, 2 or 4 once known
  MeshBuffers buf;
  std::unordered_map<std::int64_t, int> node_pos;  // node tag -> id
  std::vector<std::int64_t> tet_tags;              // (4 ntet) node tags, resolved at the end
  std::vector<std::int64_t> tet_elem;              // (ntet) element tag, for messages
  std::vector<int> tet_line;                       // (ntet) line, for messages
  std::unordered_map<std::int64_t, int> volume_label;  // volume entity tag -> label (4.1)
  SkippedElements skipped;
  bool have_nodes = false, have_elements = false;

  GmshFile(const std::string& source, std::string_view text) : r(source, text) {}

  std::string_view head() const { return r.tokens()[0]; }

  void need_line(std::string_view where) {
    if (!r.next_line()) r.fail_here("file ends inside ", where);
  }

  // Moves to item `i` (0-based) of `n` announced in a section header.
  void data_line(std::string_view what, std::int64_t i, std::int64_t n) {
    if (!r.next_line()) r.fail_here("file ends after ", i, " of ", n, " ", what, "s");
    if (head()[0] == '$')
      r.fail_here("expected ", what, " ", i + 1, " of ", n, ", found '", head(), "' (is the count in the section header right?)");
  }

  void expect_end(std::string_view end, std::string_view after) {
    if (!r.next_line()) r.fail_here("file ends before ", end);
    if (head() != end) r.fail_here("expected ", end, " after ", after, ", found '", head(), "' (is the count in the section header right?)");
  }

  void expect_tokens(std::size_t n, std::string_view what) {
    if (r.tokens().size() != n) r.fail_here("expected ", n, " values for ", what, ", found ", r.tokens().size());
  }

  int to_label(std::string_view tok, std::string_view what) {
    const std::int64_t v = r.to_int(tok, what);
    if (!label_value_ok(double(v))) r.fail_here(what, " ", v, " does not fit a 32-bit label");
    return int(v);
  }

  std::int64_t count_line(std::string_view what) {
    need_line(what);
    const std::int64_t n = r.to_int(head(), cat("the number of ", what));
    if (n < 0) r.fail_here("negative number of ", what, ": ", n);
    return n;
  }

  void add_node(std::int64_t tag, const std::vector<std::string_view>& t, std::size_t first) {
    if (buf.xyz.size() / 3 >= std::size_t(INT32_MAX)) r.fail_here("too many nodes");
    const int id = int(buf.xyz.size() / 3);
    if (!node_pos.emplace(tag, id).second) r.fail_here("node tag ", tag, " appears twice");
    static const char* axis[] = {"x", "y", "z"};
    for (int c = 0; c < 3; ++c)
      buf.xyz.push_back(r.to_coord_lazy(t[first + c], [&] { return cat("node ", tag, " ", axis[c]); }));
  }

  void add_tet(std::int64_t elem, const std::vector<std::string_view>& t, std::size_t first, int label) {
    for (int k = 0; k < 4; ++k)
      tet_tags.push_back(r.to_int_lazy(t[first + k], [&] { return cat("node tag of tetrahedron ", elem); }));
    tet_elem.push_back(elem);
    tet_line.push_back(r.line());
    buf.label.push_back(label);
  }

  void check_other(std::int64_t elem, std::int64_t type, std::size_t found) {
    const int want = gmsh_nodes_per_element(type);
    if (want >= 0 && found != std::size_t(want))
      r.fail_here("expected ", want, " node tags for ", gmsh_type_name(type), " ", elem, ", found ", found);
    skipped.add(gmsh_type_name(type));
  }

  void read_format() {
    need_line("$MeshFormat");
    const auto& t = r.tokens();
    if (t.size() < 3) r.fail_here("expected 'version file-type data-size' in $MeshFormat");
    const std::string_view v = t[0];
    if (v == "2" || v == "2.0" || v == "2.1" || v == "2.2") version = 2;
    else if (v == "4.1") version = 4;
    else r.fail_here("unsupported Gmsh format version ", v, "; export the mesh as version 4.1 or 2.2 ASCII");
    if (t[1] != "0") r.fail_here("binary Gmsh files are not supported; export the mesh as ASCII (file-type 0)");
    expect_end("$EndMeshFormat", "the format line");
  }

  // Versions 1 and 2: `tag x y z` per line.
  void read_nodes_v12(std::string_view end) {
    const std::int64_t n = count_line("nodes");
    node_pos.reserve(reserve_cap(n, r.bytes_left(), 8));
    buf.xyz.reserve(3 * reserve_cap(n, r.bytes_left(), 8));
    for (std::int64_t i = 0; i < n; ++i) {
      data_line("node", i, n);
      expect_tokens(4, "a node (tag x y z)");
      add_node(r.to_int(head(), "node tag"), r.tokens(), 1);
    }
    expect_end(end, cat(n, " nodes"));
  }

  // Version 2: `tag type ntags tag... node...`; version 1: `tag type phys elem nnodes node...`.
  void read_elements_v12(std::string_view end) {
    const std::int64_t n = count_line("elements");
    for (std::int64_t i = 0; i < n; ++i) {
      data_line("element", i, n);
      const auto& t = r.tokens();
      const std::size_t fixed = version == 1 ? 5 : 3;
      if (t.size() < fixed) r.fail_here("element line too short: expected at least ", fixed, " values");
      const std::int64_t elem = r.to_int(t[0], "element tag");
      const std::int64_t type = r.to_int(t[1], "element type");
      std::size_t first;
      int label = 0;
      if (version == 1) {
        const std::int64_t nn = r.to_int(t[4], "node count of element");
        if (nn < 0) r.fail_here("negative node count for element ", elem);
        first = 5;
        if (t.size() - first != std::size_t(nn))
          r.fail_here("element ", elem, " announces ", nn, " nodes but lists ", t.size() - first);
        if (type == kTet) label = to_label(t[2], "physical tag of tetrahedron");
      } else {
        const std::int64_t ntags = r.to_int(t[2], "tag count of element");
        if (ntags < 0 || std::size_t(ntags) > t.size() - 3)
          r.fail_here("element ", elem, " announces ", ntags, " tags but the line holds only ", t.size() - 3,
                      " more values");
        first = 3 + std::size_t(ntags);
        if (type == kTet && ntags > 0) label = to_label(t[3], "physical tag of tetrahedron");
      }
      const std::size_t found = t.size() - first;
      if (type == kTet) {
        if (found != 4) r.fail_here("expected 4 node tags for tetrahedron ", elem, ", found ", found);
        add_tet(elem, t, first, label);
      } else {
        check_other(elem, type, found);
      }
    }
    expect_end(end, cat(n, " elements"));
  }

  void read_entities_v4() {
    need_line("$Entities");
    expect_tokens(4, "the entity counts (points curves surfaces volumes)");
    std::int64_t count[4];
    for (int d = 0; d < 4; ++d) {
      count[d] = r.to_int(r.tokens()[d], "entity count");
      if (count[d] < 0) r.fail_here("negative entity count");
    }
    for (int d = 0; d < 4; ++d)
      for (std::int64_t i = 0; i < count[d]; ++i) {
        data_line("entity", i, count[d]);
        const auto& t = r.tokens();
        const std::size_t at = d == 0 ? 4 : 7;  // position of numPhysicalTags
        if (t.size() <= at) r.fail_here("entity line too short: expected at least ", at + 1, " values");
        const std::int64_t tag = r.to_int(t[0], "entity tag");
        const std::int64_t nphys = r.to_int(t[at], cat("physical tag count of entity ", tag));
        if (nphys < 0 || std::size_t(nphys) > t.size() - at - 1)
          r.fail_here("entity ", tag, " announces ", nphys, " physical tags but the line holds fewer");
        if (d == 3 && nphys > 0) volume_label[tag] = to_label(t[at + 1], cat("physical tag of volume ", tag));
      }
    expect_end("$EndEntities", "the entities");
  }

  void read_nodes_v4() {
    need_line("$Nodes");
    expect_tokens(4, "the $Nodes header (numEntityBlocks numNodes minNodeTag maxNodeTag)");
    const std::int64_t blocks = r.to_int(r.tokens()[0], "number of node blocks");
    const std::int64_t total = r.to_int(r.tokens()[1], "number of nodes");
    if (blocks < 0 || total < 0) r.fail_here("negative count in the $Nodes header");
    node_pos.reserve(reserve_cap(total, r.bytes_left(), 8));
    std::vector<std::int64_t> tags;
    for (std::int64_t b = 0; b < blocks; ++b) {
      data_line("node block", b, blocks);
      expect_tokens(4, "a node block header (entityDim entityTag parametric numNodesInBlock)");
      const std::int64_t dim = r.to_int(r.tokens()[0], "entity dimension");
      const std::int64_t param = r.to_int(r.tokens()[2], "parametric flag");
      const std::int64_t n = r.to_int(r.tokens()[3], "number of nodes in block");
      if (dim < 0 || dim > 3 || (param != 0 && param != 1) || n < 0)
        r.fail_here("bad node block header (dimension ", dim, ", parametric ", param, ", nodes ", n, ")");
      const std::size_t width = 3 + (param ? std::size_t(dim) : 0);
      tags.clear();
      for (std::int64_t i = 0; i < n; ++i) {
        data_line("node tag", i, n);
        expect_tokens(1, "a node tag");
        tags.push_back(r.to_int(head(), "node tag"));
      }
      for (std::int64_t i = 0; i < n; ++i) {
        data_line("node coordinate line", i, n);
        if (r.tokens().size() != width) expect_tokens(width, cat("the coordinates of node ", tags[i]));
        add_node(tags[i], r.tokens(), 0);  // (width checked above)
      }
    }
    if (std::int64_t(node_pos.size()) != total)
      r.fail_here("the $Nodes header announces ", total, " nodes but the blocks hold ", node_pos.size());
    expect_end("$EndNodes", cat(blocks, " node blocks"));
  }

  void read_elements_v4() {
    need_line("$Elements");
    expect_tokens(4, "the $Elements header (numEntityBlocks numElements minElementTag maxElementTag)");
    const std::int64_t blocks = r.to_int(r.tokens()[0], "number of element blocks");
    const std::int64_t total = r.to_int(r.tokens()[1], "number of elements");
    if (blocks < 0 || total < 0) r.fail_here("negative count in the $Elements header");
    std::int64_t seen = 0;
    for (std::int64_t b = 0; b < blocks; ++b) {
      data_line("element block", b, blocks);
      expect_tokens(4, "an element block header (entityDim entityTag elementType numElementsInBlock)");
      const std::int64_t dim = r.to_int(r.tokens()[0], "entity dimension");
      const std::int64_t entity = r.to_int(r.tokens()[1], "entity tag");
      const std::int64_t type = r.to_int(r.tokens()[2], "element type");
      const std::int64_t n = r.to_int(r.tokens()[3], "number of elements in block");
      if (n < 0) r.fail_here("negative number of elements in block");
      int label = 0;
      if (type == kTet) {
        if (dim != 3) r.fail_here("tetrahedra in an entity of dimension ", dim, "; expected 3");
        auto it = volume_label.find(entity);
        if (it != volume_label.end()) label = it->second;
        else if (!label_value_ok(double(entity))) r.fail_here("entity tag ", entity, " does not fit a 32-bit label");
        else label = int(entity);
      }
      for (std::int64_t i = 0; i < n; ++i) {
        data_line("element", i, n);
        const auto& t = r.tokens();
        const std::int64_t elem = r.to_int(t[0], "element tag");
        if (type == kTet) {
          if (t.size() != 5) r.fail_here("expected 4 node tags for tetrahedron ", elem, ", found ", t.size() - 1);
          add_tet(elem, t, 1, label);
        } else {
          check_other(elem, type, t.size() - 1);
        }
      }
      seen += n;
    }
    if (seen != total) r.fail_here("the $Elements header announces ", total, " elements but the blocks hold ", seen);
    expect_end("$EndElements", cat(blocks, " element blocks"));
  }

  // Skips an unknown section `$Name` up to its `$EndName`.
  void skip_section(std::string_view name) {
    const int start = r.line();
    std::string end = "$End" + std::string(name.substr(1));
    while (r.next_line()) {
      std::string h(head());
      if (h.size() == end.size() && std::equal(h.begin(), h.end(), end.begin(), [](char a, char b) {
            return std::tolower((unsigned char)a) == std::tolower((unsigned char)b);
          }))
        return;
    }
    fail(r.source(), ":", start, ": section ", name, " has no ", end);
  }

  void parse() {
    while (r.next_line()) {
      const std::string_view h = head();
      if (h.empty() || h[0] != '$') r.fail_here("expected a section such as $MeshFormat or $Nodes, found '", h, "'");
      if (version == 0 && h != "$MeshFormat" && h != "$NOD" && h != "$Comments")
        r.fail_here("expected $MeshFormat (Gmsh 2 and 4) or $NOD (Gmsh 1) first, found ", h);
      if (h == "$MeshFormat") {
        if (version != 0) r.fail_here("second $MeshFormat section");
        read_format();
      } else if (h == "$NOD" || h == "$ELM") {
        if (version == 0) version = 1;
        if (version != 1) r.fail_here(h, " is a Gmsh 1 section but the file declares version ", version);
        if (h == "$NOD") {
          if (have_nodes) r.fail_here("second node section");
          read_nodes_v12("$ENDNOD");
          have_nodes = true;
        } else {
          read_elements_v12("$ENDELM");
          have_elements = true;
        }
      } else if (h == "$Nodes") {
        if (version == 1) r.fail_here("$Nodes in a Gmsh 1 file");
        if (have_nodes) r.fail_here("second $Nodes section");
        version == 4 ? read_nodes_v4() : read_nodes_v12("$EndNodes");
        have_nodes = true;
      } else if (h == "$Elements") {
        if (version == 1) r.fail_here("$Elements in a Gmsh 1 file");
        version == 4 ? read_elements_v4() : read_elements_v12("$EndElements");
        have_elements = true;
      } else if (h == "$Entities" && version == 4) {
        read_entities_v4();
      } else {
        skip_section(h);
      }
    }
    if (!have_nodes) fail(r.source(), ": no node section ($Nodes or $NOD) found");
    if (!have_elements) fail(r.source(), ": no element section ($Elements or $ELM) found");
  }

  TetMesh finish(Diagnostics& diag) {
    buf.tet.resize(tet_tags.size());
    for (std::size_t k = 0; k < tet_tags.size(); ++k) {
      auto it = node_pos.find(tet_tags[k]);
      if (it == node_pos.end())
        fail(r.source(), ":", tet_line[k / 4], ": tetrahedron ", tet_elem[k / 4], " refers to node ", tet_tags[k],
             ", which is not in the node section");
      buf.tet[k] = it->second;
    }
    skipped.report(r.source(), diag);
    return buf.finish();
  }
};

}  // namespace

TetMesh read_gmsh(const std::string& source, std::string_view text, Diagnostics& diag) {
  GmshFile f(source, text);
  f.parse();
  return f.finish(diag);
}

}  // namespace softcut::mesh::io
