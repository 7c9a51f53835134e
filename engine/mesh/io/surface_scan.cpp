#include "mesh/io/surface_scan.hpp"

#include <cctype>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <limits>
#include <vector>

#include "core/error.hpp"

namespace softcut::mesh::io {

namespace {

bool is_space(char c) { return c == ' ' || c == '\t' || c == '\n' || c == '\r' || c == '\v' || c == '\f'; }
bool is_digit(char c) { return c >= '0' && c <= '9'; }

// A whole token as a C++ stream reads a number: [+-]digits[.digits][e[+-]digits]
// (no hex, inf or nan, which streams refuse).
bool stream_number(std::string_view t, double& v) {
  std::size_t i = 0, digits = 0;
  if (i < t.size() && (t[i] == '+' || t[i] == '-')) ++i;
  while (i < t.size() && is_digit(t[i])) ++i, ++digits;
  if (i < t.size() && t[i] == '.') {
    ++i;
    while (i < t.size() && is_digit(t[i])) ++i, ++digits;
  }
  if (digits == 0) return false;
  if (i < t.size() && (t[i] == 'e' || t[i] == 'E')) {
    std::size_t j = i + 1, exp_digits = 0;
    if (j < t.size() && (t[j] == '+' || t[j] == '-')) ++j;
    while (j < t.size() && is_digit(t[j])) ++j, ++exp_digits;
    if (exp_digits == 0) return false;
    i = j;
  }
  if (i != t.size()) return false;
  v = std::strtod(std::string(t).c_str(), nullptr);
  return std::isfinite(v);
}

// A whole token as an integer: [+-]digits, within [lo, hi].
bool stream_integer(std::string_view t, std::int64_t lo, std::int64_t hi, std::int64_t& v) {
  std::size_t i = 0;
  bool neg = false;
  if (i < t.size() && (t[i] == '+' || t[i] == '-')) neg = t[i++] == '-';
  if (i == t.size() || t.size() - i > 19) return false;
  std::int64_t x = 0;
  for (; i < t.size(); ++i) {
    if (!is_digit(t[i])) return false;
    const int d = t[i] - '0';
    if (x > (std::numeric_limits<std::int64_t>::max() - d) / 10) return false;
    x = 10 * x + d;
  }
  v = neg ? -x : x;
  return v >= lo && v <= hi;
}

// Text with line numbers, for the ASCII formats.
class Cursor {
 public:
  Cursor(const std::string& source, std::string_view text) : source_(source), text_(text) {}
  bool at_end() const { return pos_ >= text_.size(); }
  char peek() const { return text_[pos_]; }
  void advance() {
    if (text_[pos_++] == '\n') ++line_;
  }
  void skip_space() {
    while (!at_end() && is_space(peek())) advance();
  }
  // Whitespace and '#' comment lines (CGAL's skip_comment_OFF).
  void skip_comments() {
    for (;;) {
      skip_space();
      if (at_end() || peek() != '#') return;
      while (!at_end() && peek() != '\n') advance();
    }
  }
  std::string_view word() {  // the next run of non-space characters
    skip_space();
    const std::size_t from = pos_;
    while (!at_end() && !is_space(peek())) advance();
    return text_.substr(from, pos_ - from);
  }
  std::string_view rest_of_line() {  // up to (not including) '\n', which is consumed
    const std::size_t from = pos_;
    while (!at_end() && peek() != '\n') advance();
    const std::string_view l = text_.substr(from, pos_ - from);
    if (!at_end()) advance();
    return l;
  }
  int line() const { return line_; }
  template <class... Args>
  [[noreturn]] void fail_here(const Args&... args) const {
    fail(source_, ":", line_, ": ", args...);
  }

 private:
  const std::string& source_;
  std::string_view text_;
  std::size_t pos_ = 0;
  int line_ = 1;
};

// The numbers a CGAL OFF line yields: tokens up to the first that is not one.
std::vector<double> line_numbers(std::string_view line) {
  if (const std::size_t hash = line.find('#'); hash != std::string_view::npos) line = line.substr(0, hash);
  std::vector<double> out;
  std::size_t i = 0;
  while (i < line.size()) {
    while (i < line.size() && is_space(line[i])) ++i;
    const std::size_t from = i;
    while (i < line.size() && !is_space(line[i])) ++i;
    if (from == i) break;
    double v;
    if (!stream_number(line.substr(from, i - from), v)) break;
    out.push_back(v);
  }
  return out;
}

// ---- PLY ----

enum class Kind { i8, u8, i16, u16, i32, u32, f32, f64, none };

Kind ply_kind(const std::string& t) {
  if (t == "char" || t == "int8") return Kind::i8;
  if (t == "uchar" || t == "uint8") return Kind::u8;
  if (t == "short" || t == "int16") return Kind::i16;
  if (t == "ushort" || t == "uint16") return Kind::u16;
  if (t == "int" || t == "int32") return Kind::i32;
  if (t == "uint" || t == "uint32") return Kind::u32;
  if (t == "float" || t == "float32") return Kind::f32;
  if (t == "double" || t == "float64") return Kind::f64;
  return Kind::none;
}
std::size_t kind_bytes(Kind k) {
  switch (k) {
    case Kind::i8: case Kind::u8: return 1;
    case Kind::i16: case Kind::u16: return 2;
    case Kind::i32: case Kind::u32: case Kind::f32: return 4;
    default: return 8;
  }
}
bool is_integer(Kind k) { return k != Kind::f32 && k != Kind::f64; }
std::int64_t kind_min(Kind k) {
  switch (k) {
    case Kind::i8: return -128;
    case Kind::i16: return -32768;
    case Kind::i32: return std::numeric_limits<std::int32_t>::min();
    default: return 0;
  }
}
std::int64_t kind_max(Kind k) {
  switch (k) {
    case Kind::i8: return 127;
    case Kind::u8: return 255;
    case Kind::i16: return 32767;
    case Kind::u16: return 65535;
    case Kind::i32: return std::numeric_limits<std::int32_t>::max();
    default: return std::numeric_limits<std::uint32_t>::max();
  }
}

struct PlyProperty {
  std::string name;
  Kind type = Kind::none;   // scalar type, or a list's index type
  Kind count = Kind::none;  // a list's count type; none for a scalar
};
struct PlyElement {
  std::string name;
  std::uint64_t items = 0;
  std::vector<PlyProperty> properties;
  int line = 0;
  const PlyProperty* find(const std::string& n) const {
    for (const auto& p : properties)
      if (p.name == n) return &p;  // CGAL takes the first of a name
    return nullptr;
  }
};

// Reads an integer of `k` (binary) at bytes[at], in the file's byte order.
std::int64_t binary_integer(std::string_view bytes, std::size_t at, Kind k, bool big_endian) {
  const std::size_t n = kind_bytes(k);
  std::uint64_t u = 0;
  for (std::size_t i = 0; i < n; ++i) {
    const auto b = std::uint64_t(static_cast<unsigned char>(bytes[at + (big_endian ? i : n - 1 - i)]));
    u = (u << 8) | b;
  }
  if (kind_min(k) < 0 && (u >> (8 * n - 1))) return std::int64_t(u) - (std::int64_t(1) << (8 * n));
  return std::int64_t(u);
}

}  // namespace

void scan_stl(const std::string& source, std::string_view bytes) {
  // CGAL reads ASCII when the first word is "solid" and a space follows,
  // binary otherwise; each falls back to the other.
  std::size_t i = 0;
  while (i < bytes.size() && is_space(bytes[i])) ++i;
  const bool ascii = bytes.substr(i, 5) == "solid" && i + 5 < bytes.size() && is_space(bytes[i + 5]);
  if (bytes.size() < 84) {
    if (!ascii && i < bytes.size())
      fail(source, ": not an STL file: ASCII STL starts with 'solid', binary STL with an 80-byte header and a "
           "triangle count (the file has ", bytes.size(), " bytes)");
    return;
  }
  const std::uint64_t n = std::uint64_t(binary_integer(bytes, 80, Kind::u32, false));
  const std::uint64_t need = 84 + 50 * n;
  if (!ascii && bytes.size() < need)
    fail(source, ": binary STL announces ", n, " triangles (", need, " bytes) but the file has ", bytes.size(),
         " bytes: it is truncated or not an STL file");
}

void scan_off(const std::string& source, std::string_view bytes) {
  Cursor c(source, bytes);
  c.skip_comments();
  if (c.at_end()) return;  // empty: the reader finds nothing
  std::string keyword;
  while (!c.at_end() && std::isalnum(static_cast<unsigned char>(c.peek()))) keyword += c.peek(), c.advance();
  if (keyword != "OFF")
    c.fail_here("expected the OFF keyword, got '", keyword.substr(0, 40),
                "' (softcut reads plain ASCII OFF: no COFF, NOFF, 4OFF, nOFF or SKEL variants)");
  // CGAL's header reader consumes the character that ends the keyword, be it
  // a '#' ("OFF#..." is not a comment to it).
  if (!c.at_end()) c.advance();
  c.skip_comments();
  const std::string_view first = c.word();
  std::int64_t nv = 0, nf = 0, ne = 0;
  if (first == "BINARY") c.fail_here("binary OFF is not read; save the surface as ASCII OFF, STL, PLY or OBJ");
  if (first.empty() || !is_digit(first[0]) || !stream_integer(first, 0, std::numeric_limits<std::int32_t>::max(), nv))
    c.fail_here("expected the vertex count after OFF, got '", first.substr(0, 40), "'");
  if (!stream_integer(c.word(), 0, std::numeric_limits<std::int32_t>::max(), nf))
    c.fail_here("expected the face count (a whole number >= 0) after the vertex count");
  // The edge count is not used, but CGAL doubles it in an int (overflow past 2^30).
  if (!stream_integer(c.word(), -1000000000, 1000000000, ne))
    c.fail_here("expected the edge count (a whole number, |n| <= 1e9) after the face count");
  // One line per vertex and per face (CGAL's reader is line based): each
  // takes at least one byte, so the walk ends within the file.
  for (std::int64_t v = 0; v < nv; ++v) {
    c.skip_comments();
    if (c.at_end()) c.fail_here("the header announces ", nv, " vertices but the file ends after ", v);
    const int line = c.line();
    if (line_numbers(c.rest_of_line()).size() < 3) fail(source, ":", line, ": vertex ", v, " needs three coordinates x y z");
  }
  for (std::int64_t f = 0; f < nf; ++f) {
    c.skip_comments();
    if (c.at_end()) c.fail_here("the header announces ", nf, " faces but the file ends after ", f);
    const int line = c.line();
    const std::vector<double> e = line_numbers(c.rest_of_line());
    if (e.empty() || e[0] != std::floor(e[0]) || e[0] < 1 || e[0] > double(e.size()) - 1)
      fail(source, ":", line, ": face ", f, " must be 'n i1 .. in' with n its number of vertices (n numbers after it)");
    for (std::size_t k = 1; k <= std::size_t(e[0]); ++k)
      if (e[k] != std::floor(e[k]) || e[k] < 0 || e[k] >= double(nv))
        fail(source, ":", line, ": face ", f, " uses vertex ", e[k], ", not one of the ", nv, " vertices (0-based)");
  }
}

void scan_ply(const std::string& source, std::string_view bytes) {
  // Header: lines, as CGAL's getline reads them.
  std::size_t pos = 0;
  int line_no = 0;
  const auto next_line = [&](std::string_view& l) {
    if (pos >= bytes.size()) return false;
    const std::size_t nl = bytes.find('\n', pos);
    const std::size_t end = nl == std::string_view::npos ? bytes.size() : nl;
    l = bytes.substr(pos, end - pos);
    pos = nl == std::string_view::npos ? bytes.size() : nl + 1;
    ++line_no;
    return true;
  };
  const auto words = [](std::string_view l) {
    std::vector<std::string> w;
    std::size_t i = 0;
    while (i < l.size()) {
      while (i < l.size() && is_space(l[i])) ++i;
      const std::size_t from = i;
      while (i < l.size() && !is_space(l[i])) ++i;
      if (from < i) w.emplace_back(l.substr(from, i - from));
    }
    return w;
  };
  const auto fail_line = [&](const auto&... args) { fail(source, ":", line_no, ": ", args...); };
  std::string_view l;
  if (!next_line(l) || words(l).empty() || words(l)[0] != "ply") fail(source, ":1: not a PLY file (it must start with 'ply')");
  if (!next_line(l)) fail(source, ": the PLY header ends after its first line");
  const auto fmt = words(l);
  if (fmt.size() < 3 || fmt[0] != "format" ||
      (fmt[1] != "ascii" && fmt[1] != "binary_little_endian" && fmt[1] != "binary_big_endian"))
    fail_line("expected 'format ascii|binary_little_endian|binary_big_endian 1.0'");
  const bool ascii = fmt[1] == "ascii", big_endian = fmt[1] == "binary_big_endian";
  std::vector<PlyElement> elements;
  bool ended = false;
  while (!ended && next_line(l)) {
    const auto w = words(l);
    if (w.empty()) fail_line("blank line in the PLY header");
    if (w[0] == "end_header") {
      ended = true;
    } else if (w[0] == "element") {
      std::int64_t n = 0;
      if (w.size() < 3 || !stream_integer(w[2], 0, std::numeric_limits<std::int64_t>::max(), n))
        fail_line("expected 'element NAME COUNT'");
      if (w[1] == "halfedge") fail_line("PLY halfedge elements are not read; save faces only");
      elements.push_back({w[1], std::uint64_t(n), {}, line_no});
    } else if (w[0] == "property") {
      if (elements.empty()) fail_line("a property before any element");
      PlyProperty p;
      if (w.size() >= 2 && w[1] == "list") {
        if (w.size() < 5) fail_line("expected 'property list COUNT_TYPE INDEX_TYPE NAME'");
        p.count = ply_kind(w[2]), p.type = ply_kind(w[3]), p.name = w[4];
        if (p.count == Kind::none || !is_integer(p.count)) fail_line("unknown or non-integer list count type '", w[2].substr(0, 20), "'");
      } else {
        if (w.size() < 3) fail_line("expected 'property TYPE NAME'");
        p.type = ply_kind(w[1]), p.name = w[2];
      }
      if (p.type == Kind::none) fail_line("unknown PLY type (use char, uchar, short, ushort, int, uint, float, double)");
      elements.back().properties.push_back(p);
    }  // comment, obj_info and other keywords: ignored, as CGAL does
  }
  if (!ended) fail(source, ": the PLY header has no end_header line");
  bool faces = false;
  for (const auto& e : elements) {
    if (e.items > 0 && e.properties.empty())
      fail(source, ":", e.line, ": element '", e.name.substr(0, 40), "' has ", e.items, " items but no properties");
    if (e.name == "vertex" || e.name == "vertices") {
      for (const char* axis : {"x", "y", "z"}) {
        const PlyProperty* p = e.find(axis);
        if (!p || p->count != Kind::none || (p->type != Kind::f32 && p->type != Kind::f64))
          fail(source, ":", e.line, ": the vertex element needs a float or double property '", axis, "'");
      }
    } else if (e.name == "face" || e.name == "faces") {
      const PlyProperty* p = e.find("vertex_indices");
      if (!p) p = e.find("vertex_index");
      if (!p || p->count == Kind::none || (p->type != Kind::i32 && p->type != Kind::u32))
        fail(source, ":", e.line, ": the face element needs a list 'vertex_indices' of int or uint");
      faces = true;
    }
  }
  if (!faces) fail(source, ": the PLY file has no face element (a point cloud is not a surface)");

  // Body: every item of every element, as CGAL's reader walks it.
  if (ascii) {
    Cursor c(source, bytes.substr(pos));
    for (const auto& e : elements)
      for (std::uint64_t i = 0; i < e.items; ++i)
        for (const auto& p : e.properties) {
          const auto value = [&](Kind k, const char* what) {
            const std::string_view t = c.word();
            if (t.empty())
              fail(source, ": element '", e.name.substr(0, 40), "' announces ", e.items, " items; the data ends in item ", i);
            std::int64_t iv = 0;
            double dv = 0;
            if (is_integer(k) ? !stream_integer(t, kind_min(k), kind_max(k), iv) : !stream_number(t, dv))
              fail(source, ":", line_no + c.line(), ": ", what, " of ", e.name.substr(0, 40), " ", i, " ('",
                   p.name.substr(0, 40), "'): '", t.substr(0, 40), "' is not a number of its type");
            return iv;
          };
          if (p.count == Kind::none) {
            value(p.type, "value");
          } else {
            const std::int64_t n = value(p.count, "list count");
            for (std::int64_t k = 0; k < n; ++k) value(p.type, "list entry");
          }
        }
  } else {
    std::size_t at = pos;
    const auto need = [&](const PlyElement& e, std::uint64_t i, std::uint64_t n) {
      if (n > bytes.size() - at)
        fail(source, ": element '", e.name.substr(0, 40), "' item ", i, " needs ", n, " more bytes at byte ", at,
             " but the file has ", bytes.size() - at, " left (it announces ", e.items, " items)");
    };
    for (const auto& e : elements) {
      bool fixed = true;
      std::uint64_t item_bytes = 0;
      for (const auto& p : e.properties) {
        fixed = fixed && p.count == Kind::none;
        item_bytes += kind_bytes(p.type);
      }
      if (fixed) {  // one check for the whole element
        if (e.items > (bytes.size() - at) / item_bytes)
          fail(source, ": element '", e.name.substr(0, 40), "' announces ", e.items, " items of ", item_bytes,
               " bytes but the file has ", bytes.size() - at, " bytes left at byte ", at);
        at += std::size_t(e.items * item_bytes);
        continue;
      }
      for (std::uint64_t i = 0; i < e.items; ++i)
        for (const auto& p : e.properties) {
          if (p.count == Kind::none) {
            need(e, i, kind_bytes(p.type));
            at += kind_bytes(p.type);
            continue;
          }
          need(e, i, kind_bytes(p.count));
          const std::int64_t n = binary_integer(bytes, at, p.count, big_endian);
          at += kind_bytes(p.count);
          if (n < 0) fail(source, ": element '", e.name.substr(0, 40), "' item ", i, ": a negative list count ", n);
          need(e, i, std::uint64_t(n) * kind_bytes(p.type));
          at += std::size_t(n) * kind_bytes(p.type);
        }
    }
  }
}

}  // namespace softcut::mesh::io
