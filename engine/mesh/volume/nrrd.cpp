#include "mesh/volume/nrrd.hpp"

#include <zlib.h>

#include <Eigen/LU>

#include <algorithm>
#include <cctype>
#include <charconv>
#include <cmath>
#include <fstream>
#include <limits>
#include <map>
#include <sstream>

#include "core/checked_file.hpp"
#include "core/printable.hpp"

namespace softcut::mesh {
namespace {

std::string read_all(const std::filesystem::path& p, const std::string& what, std::size_t max_bytes) {
  return read_regular_file(p, what, max_bytes);
}

std::string trim(std::string_view s) {
  size_t a = 0, b = s.size();
  while (a < b && std::isspace((unsigned char)s[a])) ++a;
  while (b > a && std::isspace((unsigned char)s[b - 1])) --b;
  return std::string(s.substr(a, b - a));
}

std::string lower(std::string s) {
  for (auto& c : s) c = char(std::tolower((unsigned char)c));
  return s;
}

std::vector<std::string> words(const std::string& s) {
  std::istringstream is(s);
  std::vector<std::string> w;
  for (std::string x; is >> x;) w.push_back(x);
  return w;
}

struct Field {
  std::string value;
  int line = 0;
};

// One header, with the position of each field for messages.
class Header {
 public:
  std::string file;
  std::map<std::string, Field> fields;

  template <class... Args>
  [[noreturn]] void fail_at(const std::string& key, const Args&... args) const {
    fail(file, ":", fields.at(key).line, ": ", key, ": ", args...);
  }
  bool has(const std::string& k) const { return fields.count(k) > 0; }
  const std::string& get(const std::string& k) const { return fields.at(k).value; }

  long long integer(const std::string& k) const {
    const std::string& v = get(k);
    long long x = 0;
    auto [p, ec] = std::from_chars(v.data(), v.data() + v.size(), x);
    if (ec != std::errc() || p != v.data() + v.size()) fail_at(k, "expected an integer, got '", v, "'");
    return x;
  }
  double number(const std::string& k, const std::string& tok) const {
    const std::string t = lower(tok);
    if (t == "nan") return std::nan("");
    char* end = nullptr;
    const double x = std::strtod(tok.c_str(), &end);
    if (tok.empty() || end != tok.c_str() + tok.size() || !std::isfinite(x))
      fail_at(k, "expected a number, got '", tok, "'");
    return x;
  }
  // "(x,y,z)" -> 3 numbers.
  Eigen::Vector3d vector(const std::string& k, std::string tok) const {
    tok.erase(std::remove_if(tok.begin(), tok.end(), [](char c) { return std::isspace((unsigned char)c); }),
              tok.end());
    if (tok.size() < 2 || tok.front() != '(' || tok.back() != ')')
      fail_at(k, "expected a vector like (1,0,0), got '", tok, "'");
    std::vector<std::string> parts;
    std::string cur;
    for (char c : tok.substr(1, tok.size() - 2)) {
      if (c == ',') parts.push_back(cur), cur.clear();
      else cur += c;
    }
    parts.push_back(cur);
    if (parts.size() != 3) fail_at(k, "expected 3 components in '", tok, "' (only 3D space is supported)");
    Eigen::Vector3d v;
    for (int c = 0; c < 3; ++c) {
      v(c) = number(k, parts[size_t(c)]);
      if (std::isnan(v(c))) fail_at(k, "NaN component in '", tok, "'");
    }
    return v;
  }
  // Space-separated vectors; "(a, b, c)" may hold spaces, so split on ')'.
  std::vector<std::string> vectors(const std::string& k) const {
    std::vector<std::string> out;
    std::string cur;
    for (char c : get(k)) {
      if (std::isspace((unsigned char)c) && cur.empty()) continue;
      cur += c;
      if (c == ')' || (cur == "none")) out.push_back(cur), cur.clear();
    }
    if (!trim(cur).empty()) out.push_back(trim(cur));
    return out;
  }
};

struct Type {
  int bytes;
  bool is_signed;
};

Type parse_type(const Header& h) {
  static const std::map<std::string, Type> kTypes = {
      {"uchar", {1, false}},          {"unsigned char", {1, false}},      {"uint8", {1, false}},
      {"uint8_t", {1, false}},        {"signed char", {1, true}},         {"int8", {1, true}},
      {"int8_t", {1, true}},          {"short", {2, true}},               {"short int", {2, true}},
      {"signed short", {2, true}},    {"signed short int", {2, true}},    {"int16", {2, true}},
      {"int16_t", {2, true}},         {"ushort", {2, false}},             {"unsigned short", {2, false}},
      {"unsigned short int", {2, false}}, {"uint16", {2, false}},         {"uint16_t", {2, false}},
      {"int", {4, true}},             {"signed int", {4, true}},          {"int32", {4, true}},
      {"int32_t", {4, true}},         {"uint", {4, false}},               {"unsigned int", {4, false}},
      {"uint32", {4, false}},         {"uint32_t", {4, false}}};
  const std::string t = lower(h.get("type"));
  if (auto it = kTypes.find(t); it != kTypes.end()) return it->second;
  if (t == "float" || t == "double" || t.find("long") != std::string::npos || t.find("64") != std::string::npos)
    h.fail_at("type", "'", h.get("type"),
              "' is not a label type; labels must be 8, 16 or 32-bit integers (convert the segmentation)");
  h.fail_at("type", "unknown type '", h.get("type"), "'");
}

double unit_to_m(const Header& h, const std::string& u) {
  const std::string s = lower(u);
  if (s == "m" || s == "meter" || s == "metre") return 1;
  if (s == "cm") return 1e-2;
  if (s == "mm") return 1e-3;
  if (s == "um" || s == "micron" || s == "\xc2\xb5m") return 1e-6;
  h.fail_at("space units", "unknown length unit \"", u, "\" (use m, cm, mm or um)");
}

// Inflates gzip or zlib data (also several concatenated gzip members), at
// most `limit` bytes out.
std::string inflate_all(const std::string& in, size_t limit, const std::string& where) {
  std::string out;
  z_stream zs{};
  if (inflateInit2(&zs, 15 + 32) != Z_OK) fail(where, ": cannot start zlib");
  zs.next_in = reinterpret_cast<Bytef*>(const_cast<char*>(in.data()));
  zs.avail_in = uInt(in.size());
  char buf[1 << 16];
  for (;;) {
    zs.next_out = reinterpret_cast<Bytef*>(buf);
    zs.avail_out = sizeof buf;
    const int rc = inflate(&zs, Z_NO_FLUSH);
    out.append(buf, sizeof buf - zs.avail_out);
    if (out.size() > limit) break;  // more than needed: the caller reports trailing data
    if (rc == Z_STREAM_END) {
      if (zs.avail_in == 0) break;
      inflateReset(&zs);
      continue;
    }
    if (rc != Z_OK) {
      const std::string msg = zs.msg ? zs.msg : (rc == Z_BUF_ERROR ? "data ends early" : "error " + std::to_string(rc));
      inflateEnd(&zs);
      fail(where, ": gzip data is corrupt or truncated (zlib: ", msg, ") after ", out.size(),
           " decompressed bytes");
    }
  }
  inflateEnd(&zs);
  return out;
}

}  // namespace

static LabelVolume read_nrrd_unescaped(const std::filesystem::path& path, Diagnostics& diag, const NrrdReadOptions& opt) {
  const std::string file = path.string();
  const std::string text = read_all(path, "NRRD file", opt.max_bytes);
  Header h;
  h.file = file;
  // Header lines up to a blank line (attached data follows) or the end of the file.
  size_t pos = 0;
  int line = 0;
  bool blank_seen = false;
  while (pos < text.size()) {
    size_t eol = text.find('\n', pos);
    const bool last = eol == std::string::npos;
    if (last) eol = text.size();
    std::string_view raw(text.data() + pos, eol - pos);
    if (!raw.empty() && raw.back() == '\r') raw.remove_suffix(1);
    pos = last ? text.size() : eol + 1;
    ++line;
    if (line == 1) {
      if (raw.size() != 8 || raw.substr(0, 7) != "NRRD000" || raw[7] < '1' || raw[7] > '5')
        fail(file, ":1: not a NRRD file: the first line must be a magic NRRD0001 .. NRRD0005, got '",
             std::string(raw.substr(0, 40)), "'");
      continue;
    }
    if (raw.empty()) {
      blank_seen = true;
      break;
    }
    if (raw[0] == '#') continue;
    if (raw.find(":=") != std::string_view::npos) continue;  // key/value pair: not used
    const size_t colon = raw.find(": ");
    if (colon == std::string_view::npos)
      fail(file, ":", line, ": expected 'field: value' (or '# comment', 'key:=value'), got '",
           std::string(raw.substr(0, 60)), "'");
    std::string key = lower(trim(raw.substr(0, colon)));
    if (key == "datafile") key = "data file";
    if (key == "lineskip") key = "line skip";
    if (key == "byteskip") key = "byte skip";
    if (key == "centerings") key = "centers";
    if (h.has(key)) fail(file, ":", line, ": field '", key, "' given twice (first on line ", h.fields[key].line, ")");
    h.fields[key] = {trim(raw.substr(colon + 2)), line};
  }
  static const char* kKnown[] = {"dimension", "type", "sizes", "encoding", "endian", "spacings", "space directions",
                                 "space origin", "space", "space dimension", "space units", "data file", "line skip",
                                 "byte skip", "kinds", "centers", "content", "thicknesses", "axis mins", "axis maxs",
                                 "labels", "units", "min", "max", "old min", "old max", "measurement frame",
                                 "sample units"};
  for (const auto& [k, f] : h.fields)
    if (std::find(std::begin(kKnown), std::end(kKnown), k) == std::end(kKnown))
      diag.warn(file, ":", f.line, ": unknown NRRD field '", k, "' ignored");
  for (const char* k : {"dimension", "type", "sizes", "encoding"})
    if (!h.has(k)) fail(file, ": NRRD header lacks the required field '", k, ":'");
  if (h.integer("dimension") != 3)
    h.fail_at("dimension", "only 3D label volumes are supported, got dimension ", h.get("dimension"));
  const Type type = parse_type(h);

  LabelVolume v;
  v.source = file;
  const auto sizes = words(h.get("sizes"));
  if (sizes.size() != 3) h.fail_at("sizes", "expected 3 sizes for dimension 3, got ", sizes.size());
  for (int a = 0; a < 3; ++a) {
    long long n = 0;
    auto [p, ec] = std::from_chars(sizes[size_t(a)].data(), sizes[size_t(a)].data() + sizes[size_t(a)].size(), n);
    if (ec != std::errc() || p != sizes[size_t(a)].data() + sizes[size_t(a)].size() || n < 1 || n > (1 << 20))
      h.fail_at("sizes", "axis ", a, " size must be an integer in 1..1048576, got '", sizes[size_t(a)], "'");
    v.size(a) = int(n);
  }
  if (v.num_voxels() > (std::int64_t(1) << 31))
    h.fail_at("sizes", v.num_voxels(), " voxels is more than this reader handles (2^31); crop or downsample");

  // Geometry, in file units first.
  double unit = opt.unit_m;
  if (unit == 0) {
    if (h.has("space units")) {
      std::vector<std::string> us;
      std::string cur;
      bool in_quote = false;
      for (char c : h.get("space units")) {
        if (c == '"') {
          if (in_quote) us.push_back(cur), cur.clear();
          in_quote = !in_quote;
        } else if (in_quote) cur += c;
      }
      if (in_quote || us.empty()) h.fail_at("space units", "expected quoted units like \"mm\" \"mm\" \"mm\"");
      unit = unit_to_m(h, us[0]);
      for (const auto& u : us)
        if (unit_to_m(h, u) != unit) h.fail_at("space units", "axes with different units are not supported");
    } else {
      unit = 1e-3;
      diag.warn(file, ": no 'space units' in the header; lengths taken as millimetres");
    }
  }
  if (!(unit > 0)) fail(file, ": length unit must be > 0 m, got ", unit);
  if (h.has("space dimension") && h.integer("space dimension") != 3)
    h.fail_at("space dimension", "only 3D space is supported, got ", h.get("space dimension"));
  if (h.has("spacings") && h.has("space directions"))
    fail(file, ":", h.fields["space directions"].line, ": give either 'spacings' (line ", h.fields["spacings"].line,
         ") or 'space directions', not both");
  if (h.has("space directions")) {
    const auto vs = h.vectors("space directions");
    if (vs.size() != 3) h.fail_at("space directions", "expected 3 vectors for dimension 3, got ", vs.size());
    for (int a = 0; a < 3; ++a) {
      if (vs[size_t(a)] == "none")
        h.fail_at("space directions", "axis ", a, " is 'none'; every axis of a label volume must be spatial");
      v.directions.col(a) = h.vector("space directions", vs[size_t(a)]);
    }
  } else {
    Eigen::Vector3d sp = Eigen::Vector3d::Ones();
    if (h.has("spacings")) {
      const auto ws = words(h.get("spacings"));
      if (ws.size() != 3) h.fail_at("spacings", "expected 3 spacings for dimension 3, got ", ws.size());
      for (int a = 0; a < 3; ++a) {
        sp(a) = h.number("spacings", ws[size_t(a)]);
        if (std::isnan(sp(a))) h.fail_at("spacings", "axis ", a, " spacing is NaN; give the voxel size");
        if (sp(a) == 0) h.fail_at("spacings", "axis ", a, " spacing is 0");
      }
    } else {
      diag.warn(file, ": neither 'spacings' nor 'space directions'; voxels taken as unit cubes");
    }
    v.directions = sp.asDiagonal();
  }
  const double det = v.directions.determinant();
  if (!(std::abs(det) > 1e-12 * v.directions.colwise().norm().prod()))
    h.fail_at(h.has("space directions") ? "space directions" : "spacings",
              "the voxel axes are degenerate (zero volume)");
  v.origin = h.has("space origin") ? h.vector("space origin", h.get("space origin")) : Eigen::Vector3d::Zero();
  v.directions *= unit;
  v.origin *= unit;
  if (h.has("centers"))
    for (const auto& c : words(h.get("centers")))
      if (c != "cell" && c != "node" && c != "???" && c != "none")
        h.fail_at("centers", "unknown centering '", c, "'");

  // Data bytes.
  const std::string enc = lower(h.get("encoding"));
  const bool gzip = enc == "gzip" || enc == "gz", raw = enc == "raw", ascii = enc == "ascii" || enc == "text" ||
                                                                        enc == "txt";
  if (!gzip && !raw && !ascii)
    h.fail_at("encoding", "unsupported encoding '", h.get("encoding"), "' (use raw, gzip or ascii)");
  bool big = false;
  if (h.has("endian")) {
    const std::string e = lower(h.get("endian"));
    if (e != "little" && e != "big") h.fail_at("endian", "expected 'little' or 'big', got '", h.get("endian"), "'");
    big = e == "big";
  } else if (type.bytes > 1 && !ascii) {
    fail(file, ": NRRD header lacks 'endian:', required for ", type.bytes, "-byte ", h.get("encoding"), " data");
  }
  const long long line_skip = h.has("line skip") ? h.integer("line skip") : 0;
  const long long byte_skip = h.has("byte skip") ? h.integer("byte skip") : 0;
  if (line_skip < 0) h.fail_at("line skip", "must be >= 0");
  if (byte_skip < -1 || (byte_skip == -1 && !raw))
    h.fail_at("byte skip", "must be >= 0 (-1, 'data at the end', only with raw encoding)");

  std::string data_name = file;
  std::string data;
  if (h.has("data file")) {
    const auto ws = words(h.get("data file"));
    if (ws.size() != 1 || ws[0] == "LIST" || h.get("data file").find('%') != std::string::npos)
      h.fail_at("data file", "only a single data file is supported, got '", h.get("data file"), "'");
    // A detached data file lies below the header's folder and is opened
    // through the checked open: a shared header cannot name (or link to) a
    // file elsewhere and have its bytes echoed in a message.
    const std::filesystem::path root = std::filesystem::absolute(path).parent_path();
    const std::filesystem::path dp = std::filesystem::path(ws[0]).is_relative() ? root / ws[0] : std::filesystem::path(ws[0]);
    const std::filesystem::path rel = relative_below(root, dp);
    if (rel.empty())
      h.fail_at("data file", "'", printable(ws[0]), "' must lie beside the header or in a folder below it");
    data_name = dp.string();
    const std::string what = cat("data file named on ", file, ":", h.fields["data file"].line);
    int missing = 0;
    const UniqueFd fd = open_below_if_exists(root, rel, Access::read, what, &missing);
    if (!fd) fail(dp.string(), ": cannot open ", what, " (missing or unreadable)");
    data = read_whole(fd, what, dp.string(), opt.max_bytes);
  } else {
    if (!blank_seen)
      fail(file, ": no data: the header has no 'data file:' and no blank line followed by attached data");
    data = text.substr(pos);
  }
  size_t start = 0;
  for (long long s = 0; s < line_skip; ++s) {
    const size_t eol = data.find('\n', start);
    if (eol == std::string::npos) fail(data_name, ": ends before the ", line_skip, " lines to skip ('line skip')");
    start = eol + 1;
  }
  data.erase(0, start);
  const size_t nvox = size_t(v.num_voxels());
  const size_t need = nvox * size_t(type.bytes);
  const std::string geometry = cat("sizes ", v.size(0), " ", v.size(1), " ", v.size(2), " of type ", h.get("type"));
  // The decoded data and the labels, before anything is inflated or allocated.
  if (const double total = double(nvox) * (double(type.bytes) + sizeof(std::int32_t)) + double(data.size());
      total > double(opt.max_bytes))
    fail(file, ": ", geometry, " (", nvox, " voxels) need ", std::llround(total), " bytes decoded, more than the ",
         opt.max_bytes, " bytes allowed (", opt.raise, "); crop or downsample the image");
  // Labels are allocated only as far as the data can hold them: a header may
  // announce 2^31 voxels over a few bytes.
  if (ascii) {
    v.labels.reserve(std::min(nvox, data.size() / 2 + 1));  // a value and its separator take 2 bytes or more
    const char* p = data.data() + std::min<size_t>(size_t(std::max<long long>(byte_skip, 0)), data.size());
    const char* end = data.data() + data.size();
    const long long lo = type.is_signed ? -(1LL << (8 * type.bytes - 1)) : 0;
    const long long hi = type.is_signed ? (1LL << (8 * type.bytes - 1)) - 1 : (1LL << (8 * type.bytes)) - 1;
    for (size_t n = 0; n < nvox; ++n) {
      while (p < end && (std::isspace((unsigned char)*p) || *p == ',')) ++p;
      long long x = 0;
      auto [q, ec] = std::from_chars(p, end, x);
      if (p == end) fail(data_name, ": ascii data holds ", n, " values, ", geometry, " need ", nvox);
      if (ec != std::errc() || x < lo || x > hi)
        fail(data_name, ": ascii value ", n, " ('", std::string(p, std::min<size_t>(size_t(end - p), 20)),
             "') is not a ", h.get("type"));
      if (x > std::numeric_limits<std::int32_t>::max())
        fail(data_name, ": label ", x, " at voxel ", n, " does not fit a 32-bit signed label");
      v.labels.push_back(std::int32_t(x));
      p = q;
    }
    return v;
  }
  if (gzip) data = inflate_all(data, need + size_t(std::max<long long>(byte_skip, 0)), data_name);
  size_t off = 0;
  if (byte_skip == -1) {
    if (data.size() < need) fail(data_name, ": data has ", data.size(), " bytes, ", geometry, " need ", need);
    off = data.size() - need;
  } else {
    off = size_t(byte_skip);
    if (data.size() < off + need)
      fail(data_name, ": data has ", data.size() < off ? 0 : data.size() - off, " bytes",
           byte_skip ? cat(" after skipping ", byte_skip) : std::string(), ", ", geometry, " need ", need,
           gzip ? " (after gzip decompression)" : "");
    if (data.size() > off + need)
      diag.warn(data_name, ": ", gzip ? std::string("data") : cat(data.size() - off - need, " bytes"),
                " after the voxel data ignored");
  }
  v.labels.resize(nvox);
  const auto* b = reinterpret_cast<const unsigned char*>(data.data() + off);
  for (size_t n = 0; n < nvox; ++n, b += type.bytes) {
    std::uint32_t u = 0;
    for (int k = 0; k < type.bytes; ++k) {
      const int shift = big ? 8 * (type.bytes - 1 - k) : 8 * k;
      u |= std::uint32_t(b[k]) << shift;
    }
    long long x = u;
    if (type.is_signed && (u >> (8 * type.bytes - 1)) & 1u) x -= 1LL << (8 * type.bytes);
    if (x > std::numeric_limits<std::int32_t>::max())
      fail(data_name, ": label ", x, " at voxel ", n, " does not fit a 32-bit signed label");
    v.labels[n] = std::int32_t(x);
  }
  return v;
}

LabelVolume read_nrrd_labels(const std::filesystem::path& path, Diagnostics& diag, const NrrdReadOptions& opt) {
  try {  // messages quote the header's bytes: shown escaped
    return read_nrrd_unescaped(path, diag, opt);
  } catch (const Error& e) {
    throw Error(printable(e.what(), 4000));
  }
}

}  // namespace softcut::mesh
