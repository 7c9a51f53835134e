#include "sim/render_record.hpp"

#include <fcntl.h>
#include <unistd.h>
#include <zlib.h>

#include <algorithm>
#include <cerrno>
#include <cstring>
#include <type_traits>
#include <variant>

#include "core/error.hpp"
#include "core/output_budget.hpp"
#include "mesh/surface.hpp"

namespace softcut::sim {

namespace fs = std::filesystem;

namespace {

constexpr char kMagic[] = "softcut-render-record\n";  // 22 bytes, then the version (u32)
constexpr std::uint32_t kVersion = 1;
constexpr char kMeta = 'M', kTopology = 'T', kFrame = 'F', kEnd = 'E';

// --- writing ------------------------------------------------------------------

struct Out {
  std::string s;
  template <class T>
  void pod(const T& v) {
    static_assert(std::is_trivially_copyable_v<T>);
    s.append(reinterpret_cast<const char*>(&v), sizeof v);
  }
  void u32(std::size_t v) { pod(std::uint32_t(v)); }
  void vec(const Eigen::Vector3d& v) {
    for (int k = 0; k < 3; ++k) pod(v[k]);
  }
  template <class T>
  void array(const std::vector<T>& v) {
    u64(v.size());
    if (!v.empty()) s.append(reinterpret_cast<const char*>(v.data()), v.size() * sizeof(T));
  }
  void u64(std::size_t v) { pod(std::uint64_t(v)); }
  void matrix(const Eigen::MatrixX3d& m) {  // rows x 3, row by row
    u64(std::size_t(m.rows()));
    for (Eigen::Index r = 0; r < m.rows(); ++r) vec(m.row(r).transpose());
  }
};

void put_tool(Out& o, const render::ToolShape& t) {
  if (const auto* p = std::get_if<render::ProbeShape>(&t)) {
    o.pod(std::uint8_t(0));
    o.vec(p->tip), o.vec(p->axis), o.pod(p->radius), o.pod(p->length);
  } else if (const auto* g = std::get_if<render::GrasperShape>(&t)) {
    o.pod(std::uint8_t(1));
    o.vec(g->pivot), o.vec(g->axis), o.vec(g->hinge);
    o.pod(g->opening_deg), o.pod(g->jaw_length), o.pod(g->jaw_width), o.pod(g->shaft_length);
  } else if (const auto* c = std::get_if<render::ScalpelShape>(&t)) {
    o.pod(std::uint8_t(2));
    o.vec(c->edge_a), o.vec(c->edge_b), o.vec(c->spine), o.vec(c->handle_end), o.pod(c->handle_radius);
  }
}

void put_camera(Out& o, const render::CameraSettings& c) {
  o.pod(std::uint8_t(c.auto_frame));
  o.pod(c.azimuth_deg), o.pod(c.elevation_deg), o.pod(c.margin);
  o.vec(c.eye), o.vec(c.target), o.vec(c.up), o.pod(c.fov_y_deg);
}

// --- reading ------------------------------------------------------------------

// A bounded cursor over one inflated chunk: every read checks what is left.
class In {
 public:
  In(std::string_view s, const std::string& where) : s_(s), where_(where) {}
  template <class T>
  T pod() {
    static_assert(std::is_trivially_copyable_v<T>);
    if (s_.size() - at_ < sizeof(T)) bad("ends early");
    T v;
    std::memcpy(&v, s_.data() + at_, sizeof v);
    at_ += sizeof v;
    return v;
  }
  double num() {
    const double v = pod<double>();
    if (!std::isfinite(v)) bad("holds a number that is not finite");
    return v;
  }
  Eigen::Vector3d vec() {
    Eigen::Vector3d v;
    for (int k = 0; k < 3; ++k) v[k] = num();
    return v;
  }
  // A count of items of `item` bytes each, checked against `max` and the bytes left.
  std::size_t count(std::size_t item, std::uint64_t max, const char* what) {
    const std::uint64_t n = pod<std::uint64_t>();
    if (n > max) bad(cat("has ", n, " ", what, ", more than the limit ", max));
    if (item > 0 && n > (s_.size() - at_) / item) bad(cat("claims ", n, " ", what, " but ends before them"));
    return std::size_t(n);
  }
  template <class T>
  std::vector<T> array(std::uint64_t max, const char* what) {
    const std::size_t n = count(sizeof(T), max, what);
    std::vector<T> v(n);
    if (n) std::memcpy(v.data(), s_.data() + at_, n * sizeof(T));
    at_ += n * sizeof(T);
    return v;
  }
  Eigen::MatrixX3d matrix(std::uint64_t max, const char* what) {
    const std::size_t n = count(24, max, what);
    Eigen::MatrixX3d m(Eigen::Index(n), 3);
    for (std::size_t r = 0; r < n; ++r) m.row(Eigen::Index(r)) = vec().transpose();
    return m;
  }
  void end() const {
    if (at_ != s_.size()) bad(cat("has ", s_.size() - at_, " bytes after its end"));
  }
  [[noreturn]] void bad(const std::string& why) const { fail(where_, " ", why); }

 private:
  std::string_view s_;
  std::string where_;
  std::size_t at_ = 0;
};

render::ToolShape get_tool(In& in) {
  const auto kind = in.pod<std::uint8_t>();
  if (kind == 0) {
    render::ProbeShape p;
    p.tip = in.vec(), p.axis = in.vec(), p.radius = in.num(), p.length = in.num();
    return p;
  }
  if (kind == 1) {
    render::GrasperShape g;
    g.pivot = in.vec(), g.axis = in.vec(), g.hinge = in.vec();
    g.opening_deg = in.num(), g.jaw_length = in.num(), g.jaw_width = in.num(), g.shaft_length = in.num();
    return g;
  }
  if (kind == 2) {
    render::ScalpelShape c;
    c.edge_a = in.vec(), c.edge_b = in.vec(), c.spine = in.vec(), c.handle_end = in.vec();
    c.handle_radius = in.num();
    return c;
  }
  in.bad(cat("has a tool of unknown kind ", int(kind)));
}

render::CameraSettings get_camera(In& in) {
  render::CameraSettings c;
  c.auto_frame = in.pod<std::uint8_t>() != 0;
  c.azimuth_deg = in.num(), c.elevation_deg = in.num(), c.margin = in.num();
  c.eye = in.vec(), c.target = in.vec(), c.up = in.vec(), c.fov_y_deg = in.num();
  return c;
}

bool same_topology(const RecordTopology& t, const mesh::TetMesh& m, const render::SceneContent& c) {
  return t.mesh.tets.rows() == m.tets.rows() && t.mesh.nodes.rows() == m.nodes.rows() && t.mesh.tets == m.tets &&
         t.mesh.nodes == m.nodes && t.operational == c.operational && t.cut_faces == c.cut_faces &&
         t.tet_group == c.tet_group && t.interface_nodes == c.interface_nodes && t.group_labels == c.group_labels &&
         t.cut_label == c.cut_label;
}

// The nodes a frame's scene reads positions of, apart from manipulated
// nodes: the boundary surface, the boundaries between tissue groups, the
// interface nodes.
std::vector<int> shown_nodes(const RecordTopology& t) {
  std::vector<char> shown(std::size_t(t.mesh.num_nodes()), 0);
  for (int v : mesh::extract_surface(t.mesh).nodes) shown[std::size_t(v)] = 1;
  if (!t.tet_group.empty()) {
    const mesh::Surface inner = mesh::group_boundaries(t.mesh, t.tet_group);
    for (Eigen::Index f = 0; f < inner.faces.rows(); ++f)
      for (int k = 0; k < 3; ++k) shown[std::size_t(inner.faces(f, k))] = 1;
  }
  for (int v : t.interface_nodes)
    if (v >= 0 && v < t.mesh.num_nodes()) shown[std::size_t(v)] = 1;
  std::vector<int> ids;
  for (std::size_t v = 0; v < shown.size(); ++v)
    if (shown[v]) ids.push_back(int(v));
  return ids;
}

}  // namespace

void scene_inputs(const RecordTopology& topo, const RecordFrame& f, Eigen::MatrixX3d& positions,
                  render::SceneContent& content) {
  positions = topo.mesh.nodes;
  for (std::size_t i = 0; i < topo.shown_nodes.size(); ++i)
    positions.row(topo.shown_nodes[i]) = f.positions.row(Eigen::Index(i));
  for (std::size_t i = 0; i < f.extra_nodes.size(); ++i)
    positions.row(f.extra_nodes[i]) = f.extra_positions.row(Eigen::Index(i));
  content = f.content;
  content.operational = topo.operational;
  content.cut_faces = topo.cut_faces;
  content.tet_group = topo.tet_group;
  content.interface_nodes = topo.interface_nodes;
  content.group_labels = topo.group_labels;
  content.cut_label = topo.cut_label;
}

// --- RenderRecordWriter -------------------------------------------------------

RenderRecordWriter::RenderRecordWriter(const fs::path& dir, const Json& meta, OutputBudget* budget)
    : dir_(dir), tmp_(dir / (std::string(kRenderRecordFile) + ".partial")), budget_(budget) {
  std::error_code ec;
  fs::remove(tmp_, ec);  // a stale one, or a planted link: the file is made new below
  const int fd = ::open(tmp_.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_NOFOLLOW | O_CLOEXEC, 0644);
  if (fd < 0 || !(file_ = ::fdopen(fd, "wb"))) {
    const int err = errno;
    if (fd >= 0) ::close(fd);
    fail("outputs: cannot write ", tmp_.string(), " (", std::strerror(err), ")");
  }
  Out head;
  head.s.append(kMagic, sizeof kMagic - 1);
  head.pod(kVersion);
  if (std::fwrite(head.s.data(), 1, head.s.size(), file_) != head.s.size())
    fail("outputs: writing ", tmp_.string(), " failed (disk full?)");
  bytes_ += head.s.size();
  chunk(kMeta, json_text(meta));
}

RenderRecordWriter::~RenderRecordWriter() {
  if (!file_) return;
  std::fclose(file_);
  std::error_code ec;
  fs::remove(tmp_, ec);
}

void RenderRecordWriter::chunk(char kind, const std::string& raw) {
  uLongf packed_size = compressBound(uLong(raw.size()));
  std::string packed(packed_size, '\0');
  if (compress2(reinterpret_cast<Bytef*>(packed.data()), &packed_size, reinterpret_cast<const Bytef*>(raw.data()),
                uLong(raw.size()), 1) != Z_OK)
    fail("outputs: compressing a chunk of ", tmp_.string(), " failed");
  packed.resize(packed_size);
  Out c;
  c.pod(kind);
  c.u64(packed.size());
  c.u64(raw.size());
  c.s += packed;
  c.pod(std::uint32_t(crc32(0L, reinterpret_cast<const Bytef*>(raw.data()), uInt(raw.size()))));
  if (budget_) budget_->charge(c.s.size(), kRenderRecordFile);
  if (std::fwrite(c.s.data(), 1, c.s.size(), file_) != c.s.size())
    fail("outputs: writing ", tmp_.string(), " failed (disk full?)");
  bytes_ += c.s.size();
}

void RenderRecordWriter::add(int frame, double time, const mesh::TetMesh& mesh, const Eigen::MatrixX3d& positions,
                             const render::SceneContent& content, const render::CameraSettings& camera) {
  if (finished_) fail("outputs: a render-record frame after finish()");
  if (positions.rows() != mesh.num_nodes()) fail("outputs: render record: positions do not match the mesh");
  if (topologies_ == 0 || !same_topology(last_, mesh, content)) {
    last_.mesh.nodes = mesh.nodes;
    last_.mesh.tets = mesh.tets;
    last_.operational = content.operational;
    last_.cut_faces = content.cut_faces;
    last_.tet_group = content.tet_group;
    last_.interface_nodes = content.interface_nodes;
    last_.group_labels = content.group_labels;
    last_.cut_label = content.cut_label;
    last_.shown_nodes = shown_nodes(last_);
    Out t;
    t.matrix(mesh.nodes);
    std::vector<std::int32_t> tets(std::size_t(4) * std::size_t(mesh.num_tets()));
    for (int i = 0; i < mesh.num_tets(); ++i)
      for (int k = 0; k < 4; ++k) tets[std::size_t(4 * i + k)] = mesh.tets(i, k);
    t.array(tets);
    t.array(last_.operational);
    t.array(last_.cut_faces);
    t.array(last_.tet_group);
    t.array(last_.interface_nodes);
    t.array(last_.shown_nodes);
    t.array(last_.group_labels);
    t.pod(std::uint32_t(last_.cut_label));
    chunk(kTopology, t.s);
    ++topologies_;
  }
  Out f;
  f.pod(std::int32_t(frame));
  f.pod(time);
  f.u32(std::size_t(topologies_ - 1));
  f.u64(last_.shown_nodes.size());
  for (int v : last_.shown_nodes) f.vec(positions.row(v).transpose());
  std::vector<int> extra;
  for (const render::ManipulatedNode& mn : content.manipulated)
    if (!std::binary_search(last_.shown_nodes.begin(), last_.shown_nodes.end(), mn.node) &&
        std::find(extra.begin(), extra.end(), mn.node) == extra.end())
      extra.push_back(mn.node);
  f.u64(extra.size());
  for (int v : extra) f.pod(std::int32_t(v)), f.vec(positions.row(v).transpose());
  f.u64(content.manipulated.size());
  for (const render::ManipulatedNode& mn : content.manipulated) f.pod(std::int32_t(mn.node)), f.vec(mn.line_end);
  f.u64(content.arrows.size());
  for (const render::Arrow& a : content.arrows) f.vec(a.from), f.vec(a.to);
  f.u64(content.tools.size());
  for (std::size_t i = 0; i < content.tools.size(); ++i) {
    f.pod(std::uint32_t(i < content.tool_labels.size() ? content.tool_labels[i] : 0));
    put_tool(f, content.tools[i]);
  }
  put_camera(f, camera);
  chunk(kFrame, f.s);
  ++frames_;
}

void RenderRecordWriter::finish() {
  if (finished_) return;
  finished_ = true;
  Out e;
  e.u64(std::size_t(frames_));
  chunk(kEnd, e.s);
  const bool ok = std::fflush(file_) == 0 && !std::ferror(file_);
  std::fclose(file_);
  file_ = nullptr;
  std::error_code ec;
  if (!ok) {
    fs::remove(tmp_, ec);
    fail("outputs: writing ", tmp_.string(), " failed (disk full?)");
  }
  fs::rename(tmp_, dir_ / kRenderRecordFile, ec);
  if (ec) fail("outputs: cannot rename ", tmp_.string(), " to ", kRenderRecordFile, ": ", ec.message());
}

// --- RenderRecordReader -------------------------------------------------------

RenderRecordReader::RenderRecordReader(std::string_view bytes, std::string what, RecordLimits limits)
    : bytes_(bytes), what_(std::move(what)), limits_(limits) {
  const std::size_t magic = sizeof kMagic - 1;
  if (bytes_.size() < magic + 4 || bytes_.substr(0, magic) != std::string_view(kMagic, magic))
    fail(what_, ": not a softcut render record (it does not start with \"softcut-render-record\")");
  std::uint32_t version = 0;
  std::memcpy(&version, bytes_.data() + magic, 4);
  if (version != kVersion)
    fail(what_, ": render record version ", version, "; this softcut reads version ", kVersion,
         " (re-run the scenario to record it again)");
  at_ = magic + 4;
  char kind = 0;
  const std::string meta = read_chunk(kind);
  if (kind != kMeta) bad("the first chunk is not the meta data");
  meta_ = Json::parse(meta, nullptr, false);
  if (meta_.is_discarded() || !meta_.is_object()) bad("the meta data is not a JSON object");
}

void RenderRecordReader::bad(const std::string& why) const { fail(what_, ": chunk ", chunk_, ": ", why); }

std::string RenderRecordReader::read_chunk(char& kind) {
  ++chunk_;
  const std::size_t head = 1 + 8 + 8;
  if (bytes_.size() - at_ < head) bad("the file ends inside a chunk header (a run that was killed?)");
  kind = bytes_[at_];
  std::uint64_t packed = 0, raw = 0;
  std::memcpy(&packed, bytes_.data() + at_ + 1, 8);
  std::memcpy(&raw, bytes_.data() + at_ + 9, 8);
  at_ += head;
  if (packed > bytes_.size() - at_ || bytes_.size() - at_ - packed < 4)
    bad(cat("claims ", packed, " bytes but the file ends before them"));
  if (raw > limits_.max_chunk_bytes) bad(cat("inflates to ", raw, " bytes, more than the limit ", limits_.max_chunk_bytes));
  std::string out(std::size_t(raw), '\0');
  uLongf got = uLongf(raw);
  if (uncompress(reinterpret_cast<Bytef*>(out.data()), &got, reinterpret_cast<const Bytef*>(bytes_.data() + at_),
                 uLong(packed)) != Z_OK ||
      got != raw)
    bad("its data does not inflate to its stated size");
  at_ += std::size_t(packed);
  std::uint32_t crc = 0;
  std::memcpy(&crc, bytes_.data() + at_, 4);
  at_ += 4;
  if (crc != std::uint32_t(crc32(0L, reinterpret_cast<const Bytef*>(out.data()), uInt(out.size()))))
    bad("its checksum does not match (a corrupt file)");
  return out;
}

bool RenderRecordReader::next(RecordFrame& f) {
  for (;;) {
    if (ended_) return false;
    char kind = 0;
    const std::string raw = read_chunk(kind);
    In in(raw, cat(what_, ": chunk ", chunk_));
    if (kind == kEnd) {
      const auto n = in.pod<std::uint64_t>();
      in.end();
      if (n != std::uint64_t(frames_)) in.bad(cat("says ", n, " frames; the file holds ", frames_));
      if (at_ != bytes_.size()) in.bad("is followed by more bytes");
      ended_ = true;
      return false;
    }
    if (kind == kTopology) {
      RecordTopology t;
      t.mesh.nodes = in.matrix(limits_.max_nodes, "nodes");
      const auto tets = in.array<std::int32_t>(4 * limits_.max_tets, "tet corners");
      if (tets.size() % 4) in.bad("has a tet corner count that is not a multiple of 4");
      const int nn = int(t.mesh.nodes.rows()), nt = int(tets.size() / 4);
      t.mesh.tets.resize(nt, 4);
      for (int i = 0; i < nt; ++i)
        for (int k = 0; k < 4; ++k) {
          const int v = tets[std::size_t(4 * i + k)];
          if (v < 0 || v >= nn) in.bad(cat("tet ", i, " names node ", v, " of ", nn));
          t.mesh.tets(i, k) = v;
        }
      t.mesh.labels = Eigen::VectorXi::Zero(nt);
      t.operational = in.array<char>(limits_.max_tets, "region flags");
      t.cut_faces = in.array<char>(4 * limits_.max_tets, "cut-face flags");
      t.tet_group = in.array<int>(limits_.max_tets, "tissue groups");
      t.interface_nodes = in.array<int>(limits_.max_nodes, "interface nodes");
      t.shown_nodes = in.array<int>(limits_.max_nodes, "shown nodes");
      t.group_labels = in.array<std::uint32_t>(limits_.max_tets + 1, "group labels");
      t.cut_label = in.pod<std::uint32_t>();
      in.end();
      for (std::uint32_t id : t.group_labels)
        if (id > 255) in.bad(cat("has a label id ", id, " (at most 255)"));
      if (t.cut_label > 255) in.bad(cat("has a cut label id ", t.cut_label, " (at most 255)"));
      if (!t.operational.empty() && int(t.operational.size()) != nt) in.bad("has region flags for another tet count");
      if (!t.cut_faces.empty() && int(t.cut_faces.size()) != 4 * nt) in.bad("has cut-face flags for another tet count");
      if (!t.tet_group.empty() && int(t.tet_group.size()) != nt) in.bad("has tissue groups for another tet count");
      for (int g : t.tet_group)
        if (g < 0 || g > 1000000) in.bad(cat("has a tissue group ", g));
      for (int v : t.interface_nodes)
        if (v < 0 || v >= nn) in.bad(cat("has interface node ", v, " of ", nn));
      for (std::size_t i = 0; i < t.shown_nodes.size(); ++i)
        if (t.shown_nodes[i] < 0 || t.shown_nodes[i] >= nn || (i && t.shown_nodes[i] <= t.shown_nodes[i - 1]))
          in.bad("has shown nodes out of range or out of order");
      topologies_.push_back(std::move(t));
      continue;
    }
    if (kind != kFrame) in.bad(cat("has unknown kind ", int(static_cast<unsigned char>(kind))));
    if (std::uint64_t(frames_) >= limits_.max_frames) in.bad(cat("is past the frame limit ", limits_.max_frames));
    f = RecordFrame{};
    f.frame = in.pod<std::int32_t>();
    f.time = in.num();
    const auto topo = in.pod<std::uint32_t>();
    if (topo >= topologies_.size()) in.bad(cat("refers to topology ", topo, " of ", topologies_.size()));
    f.topology = int(topo);
    const RecordTopology& t = topologies_[topo];
    const int nn = t.mesh.num_nodes();
    f.positions = in.matrix(limits_.max_nodes, "positions");
    if (f.positions.rows() != Eigen::Index(t.shown_nodes.size()))
      in.bad(cat("holds ", f.positions.rows(), " positions for ", t.shown_nodes.size(), " shown nodes"));
    const std::size_t extra = in.count(28, limits_.max_items, "extra nodes");
    f.extra_positions.resize(Eigen::Index(extra), 3);
    for (std::size_t i = 0; i < extra; ++i) {
      const int v = in.pod<std::int32_t>();
      if (v < 0 || v >= nn) in.bad(cat("has extra node ", v, " of ", nn));
      f.extra_nodes.push_back(v);
      f.extra_positions.row(Eigen::Index(i)) = in.vec().transpose();
    }
    const std::size_t nm = in.count(28, limits_.max_items, "manipulated nodes");
    for (std::size_t i = 0; i < nm; ++i) {
      render::ManipulatedNode mn;
      mn.node = in.pod<std::int32_t>();
      if (mn.node < 0 || mn.node >= nn) in.bad(cat("has manipulated node ", mn.node, " of ", nn));
      mn.line_end = in.vec();
      f.content.manipulated.push_back(mn);
    }
    const std::size_t na = in.count(48, limits_.max_items, "arrows");
    for (std::size_t i = 0; i < na; ++i) f.content.arrows.push_back({in.vec(), in.vec()});
    const std::size_t nt = in.count(5, limits_.max_items, "tools");
    for (std::size_t i = 0; i < nt; ++i) {
      const auto tool_label = in.pod<std::uint32_t>();
      if (tool_label > 255) in.bad(cat("has a tool label id ", tool_label, " (at most 255)"));
      f.content.tool_labels.push_back(tool_label);
      f.content.tools.push_back(get_tool(in));
    }
    f.camera = get_camera(in);
    in.end();
    ++frames_;
    return true;
  }
}

const RecordTopology& RenderRecordReader::topology(int i) const {
  if (i < 0 || i >= int(topologies_.size())) fail(what_, ": no topology ", i);
  return topologies_[std::size_t(i)];
}

}  // namespace softcut::sim
