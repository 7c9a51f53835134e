#include "app/reference_log.hpp"

#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <charconv>
#include <cmath>
#include <cstring>
#include <nlohmann/json.hpp>

#include "core/error.hpp"
#include "core/printable.hpp"

namespace fs = std::filesystem;

namespace softcut::app {

namespace {

constexpr std::string_view kHeaderTag = "# softcut-reference: ";
// Header fields are cut to this many bytes each, and at most this many
// parameters are kept: the header stays one short line whatever --set gave.
constexpr std::size_t kMaxHeaderField = 200;
constexpr std::size_t kMaxHeaderParams = 100;

// Lines of an open log, one at a time, from a fixed buffer: memory does not
// grow with the file, and a line longer than kMaxLogLine is an error (a file
// of zeros or of one endless line is refused at its first 64 KiB).
class LineReader {
 public:
  LineReader(UniqueFd fd, std::string name, const CompareLimits& limits)
      : fd_(std::move(fd)), name_(std::move(name)), limits_(limits) {}

  // The next line without its "\n" or "\r\n"; false at the end.
  bool next(std::string& line) {
    if (pushed_back_) {
      pushed_back_ = false;
      line = std::move(held_);
      return true;
    }
    line.clear();
    bool any = false;
    for (;;) {
      if (pos_ == len_ && !fill()) {
        if (!any) return false;
        break;
      }
      any = true;
      const char* start = buf_ + pos_;
      const void* nl = std::memchr(start, '\n', len_ - pos_);
      const std::size_t take = nl ? std::size_t(static_cast<const char*>(nl) - start) : len_ - pos_;
      if (line.size() + take > kMaxLogLine)
        fail(name_, ":", lineno_ + 1, ": a line longer than ", kMaxLogLine,
             " bytes: not a displacement log (frame,time,node,ux,uy,uz)");
      line.append(start, take);
      pos_ += take;
      if (nl) {
        ++pos_;
        break;
      }
    }
    ++lineno_;
    if (!line.empty() && line.back() == '\r') line.pop_back();
    return true;
  }
  // Gives `line` back: the next next() returns it again.
  void push_back(std::string line) {
    held_ = std::move(line);
    pushed_back_ = true;
  }
  // Reading past `bytes` fails with `why` (after the file's name).
  void limit(std::uint64_t bytes, std::string why) {
    max_bytes_ = bytes;
    limit_why_ = std::move(why);
  }
  long lineno() const { return lineno_ - (pushed_back_ ? 1 : 0); }
  std::uint64_t bytes_read() const { return read_; }
  const std::string& name() const { return name_; }
  int fd() const { return fd_.get(); }

 private:
  bool fill() {
    if (limits_.timeout && limits_.timeout->load())
      fail(name_, ": the wall-clock limit of ", limits_.timeout_s, " s (--timeout) passed while it was read");
    if (limits_.interrupt && limits_.interrupt->load()) fail(name_, ": interrupted while it was read");
    if (read_ > max_bytes_) fail(name_, ": ", limit_why_);
    for (;;) {
      const ssize_t n = ::read(fd_.get(), buf_, sizeof buf_);
      if (n < 0 && errno == EINTR) continue;
      if (n < 0) fail(name_, ": read error (", std::strerror(errno), ")");
      pos_ = 0, len_ = std::size_t(n);
      read_ += std::uint64_t(n);
      return n > 0;
    }
  }

  UniqueFd fd_;
  std::string name_;
  const CompareLimits& limits_;
  char buf_[1 << 16];
  std::size_t pos_ = 0, len_ = 0;
  long lineno_ = 0;
  std::uint64_t read_ = 0;
  bool pushed_back_ = false;
  std::string held_;
  std::uint64_t max_bytes_ = UINT64_MAX;
  std::string limit_why_;
};

struct Row {
  long frame = 0, node = 0;
  double u[3] = {0, 0, 0};
};

std::string_view trimmed(std::string_view s) {
  while (!s.empty() && (s.front() == ' ' || s.front() == '\t')) s.remove_prefix(1);
  while (!s.empty() && (s.back() == ' ' || s.back() == '\t')) s.remove_suffix(1);
  return s;
}

template <class T>
bool parse_number(std::string_view s, T& out) {
  s = trimmed(s);
  if (!s.empty() && s.front() == '+') s.remove_prefix(1);
  const auto [end, ec] = std::from_chars(s.data(), s.data() + s.size(), out);
  return !s.empty() && ec == std::errc() && end == s.data() + s.size();
}

// "frame,time,node,ux,uy,uz" (the time is read but not compared).
bool parse_row(std::string_view line, Row& r) {
  std::string_view f[6];
  for (int k = 0; k < 6; ++k) {
    const size_t comma = line.find(',');
    if ((comma == std::string_view::npos) != (k == 5)) return false;
    f[k] = line.substr(0, comma);
    line = comma == std::string_view::npos ? std::string_view() : line.substr(comma + 1);
  }
  double time = 0;
  return parse_number(f[0], r.frame) && parse_number(f[1], time) && parse_number(f[2], r.node) &&
         parse_number(f[3], r.u[0]) && parse_number(f[4], r.u[1]) && parse_number(f[5], r.u[2]);
}

// The next data row (blank lines, '#' comments and the column header are
// skipped); false at the end.
bool next_row(LineReader& in, Row& r, std::string& line) {
  while (in.next(line)) {
    if (trimmed(line).empty() || line[0] == '#' || line.rfind("frame", 0) == 0) continue;
    if (!parse_row(line, r)) fail(in.name(), ":", in.lineno(), ": expected frame,time,node,ux,uy,uz");
    return true;
  }
  return false;
}

std::string cut(const std::string& s) { return s.size() <= kMaxHeaderField ? s : s.substr(0, kMaxHeaderField); }

// The header of a reference, if its first line is one; else the line goes back.
ReferenceHeader read_header(LineReader& in) {
  ReferenceHeader h;
  std::string line;
  if (!in.next(line)) return h;
  if (line.rfind(kHeaderTag, 0) != 0) {
    in.push_back(std::move(line));
    return h;
  }
  const std::string where = cat(in.name(), ":1: the reference header ");
  try {
    const nlohmann::json j = nlohmann::json::parse(line.substr(kHeaderTag.size()));
    if (!j.is_object()) fail(where, "is not a JSON object");
    auto text = [&](const char* key) {
      const auto it = j.find(key);
      if (it == j.end() || !it->is_string()) fail(where, "has no '", key, "' (a string); re-record the reference");
      return cut(it->get<std::string>());
    };
    h.scenario = text("scenario");
    h.mesh = text("mesh");
    h.softcut = text("softcut");
    const auto params = j.find("params");
    if (params == j.end() || !params->is_object()) fail(where, "has no 'params' (an object); re-record the reference");
    for (const auto& [k, v] : params->items()) {
      if (!v.is_string()) fail(where, "has a parameter '", printable(k, 40), "' that is not a string");
      if (h.params.size() < kMaxHeaderParams) h.params.emplace_back(cut(k), cut(v.get<std::string>()));
    }
  } catch (const nlohmann::json::exception& e) {
    fail(where, "is not valid JSON (", e.what(), "); re-record the reference");
  }
  h.present = true;
  return h;
}

LineReader open_log(const LogFile& f, const CompareLimits& limits, const char* what) {
  return LineReader(open_below(f.root, f.rel, Access::read, what), f.shown(), limits);
}

std::string params_text(const std::vector<std::pair<std::string, std::string>>& params) {
  std::string s;
  for (const auto& [k, v] : params) s += (s.empty() ? "" : " ") + k + "=" + v;
  return s.empty() ? "no parameters" : printable(s, 200);
}

// What differs between the run and the reference's header, for a failed
// comparison: " (the reference was recorded with ..., this run has ...)".
std::string identity_note(const ReferenceHeader& h, const RunIdentity* who) {
  if (!who || !h.present) return "";
  std::vector<std::pair<std::string, std::string>> mine = who->params;
  for (auto& [k, v] : mine) k = cut(k), v = cut(v);
  if (mine.size() > kMaxHeaderParams) mine.resize(kMaxHeaderParams);
  std::string note;
  if (h.params != mine)
    note += cat("the reference was recorded with ", params_text(h.params), ", this run has ", params_text(mine));
  if (h.mesh != who->mesh)
    note += cat(note.empty() ? "the reference was recorded" : ";", " on another mesh (", printable(h.mesh, 40),
                ", this run's ", who->mesh, ")");
  if (!note.empty() && h.softcut != SOFTCUT_VERSION) note += cat("; it was recorded by softcut ", printable(h.softcut, 40));
  return note.empty() ? "" : " (" + note + ")";
}

}  // namespace

LogFile LogFile::at(const fs::path& path) {
  return {path.has_parent_path() ? path.parent_path() : fs::path("."), path.filename()};
}

std::string LogFile::shown() const { return root == "." ? rel.string() : (root / rel).string(); }

fs::path reference_path(const fs::path& scenario) {
  return scenario.parent_path() / (scenario.stem().string() + ".ref.csv");
}

std::string mesh_fingerprint(const mesh::TetMesh& m) {
  std::uint64_t h = 1469598103934665603ull;  // FNV-1a, 64 bits
  auto mix = [&](const void* data, std::size_t bytes) {
    const auto* p = static_cast<const unsigned char*>(data);
    for (std::size_t i = 0; i < bytes; ++i) h = (h ^ p[i]) * 1099511628211ull;
  };
  const std::int64_t counts[3] = {m.nodes.rows(), m.tets.rows(), m.labels.size()};
  mix(counts, sizeof counts);
  mix(m.nodes.data(), sizeof(double) * std::size_t(m.nodes.size()));
  mix(m.tets.data(), sizeof(int) * std::size_t(m.tets.size()));
  mix(m.labels.data(), sizeof(int) * std::size_t(m.labels.size()));
  char buf[32];
  std::snprintf(buf, sizeof buf, "fnv1a64:%016llx", static_cast<unsigned long long>(h));
  return buf;
}

std::string reference_header_line(const ReferenceHeader& h) {
  nlohmann::ordered_json j;
  j["scenario"] = cut(h.scenario);
  j["mesh"] = cut(h.mesh);
  j["params"] = nlohmann::ordered_json::object();
  for (std::size_t i = 0; i < h.params.size() && i < kMaxHeaderParams; ++i) j["params"][cut(h.params[i].first)] = cut(h.params[i].second);
  j["softcut"] = cut(h.softcut);
  // One line whatever the strings hold: JSON escapes line breaks; bytes that
  // are not UTF-8 become U+FFFD.
  return std::string(kHeaderTag) + j.dump(-1, ' ', false, nlohmann::ordered_json::error_handler_t::replace) + "\n";
}

ReferenceHeader read_reference_header(const LogFile& reference) {
  const CompareLimits none;
  LineReader in = open_log(reference, none, "reference log");
  return read_header(in);
}

LogComparison compare_logs(const LogFile& produced, const LogFile& reference, double tolerance,
                           const RunIdentity* who, const CompareLimits& limits) {
  LineReader a = open_log(produced, limits, "displacement log");
  LineReader b = open_log(reference, limits, "reference log");
  LogComparison c;
  c.header = read_header(b);
  if (who && c.header.present && c.header.scenario != who->scenario) {
    c.foreign = true;
    c.message = cat("this reference was made by scenario '", printable(c.header.scenario, 100), "', not '",
                    printable(who->scenario, 100), "'");
    return c;
  }
  // The reference is read no further than the log allows: twice its bytes
  // and a MiB for comments (a reference of a billion blank lines ends here).
  struct stat st {};
  const std::uint64_t produced_bytes = ::fstat(a.fd(), &st) == 0 ? std::uint64_t(st.st_size) : 0;
  const std::uint64_t max_ref_bytes = 2 * produced_bytes + (1u << 20);
  b.limit(max_ref_bytes, cat("more than ", max_ref_bytes, " bytes, over twice the log it is compared with (and a "
                             "MiB): not this scenario's reference; re-record it"));
  std::string la, lb;
  Row ra, rb;
  long rows = 0;
  for (;;) {
    const bool has_a = next_row(a, ra, la);
    const bool has_b = next_row(b, rb, lb);
    if (!has_a && !has_b) break;
    if (has_a != has_b) {
      c.stale = true;
      if (has_a) {
        long total = rows + 1;
        while (next_row(a, ra, la)) ++total;
        c.message = cat("the log has ", total, " rows, the reference ", rows, " (frames or logged nodes changed)");
      } else {
        c.message = cat("the log has ", rows, " rows, the reference more (frames or logged nodes changed)");
      }
      c.message += identity_note(c.header, who);
      return c;
    }
    ++rows;
    if (ra.frame != rb.frame || ra.node != rb.node) {
      c.stale = true;
      c.message = cat("row ", rows, " is frame ", ra.frame, " node ", ra.node, ", the reference has frame ", rb.frame,
                      " node ", rb.node, " (", b.name(), ":", b.lineno(), ")") + identity_note(c.header, who);
      return c;
    }
    for (int k = 0; k < 3; ++k) {
      c.scale = std::max(c.scale, std::abs(rb.u[k]));
      const double d = std::abs(ra.u[k] - rb.u[k]);
      if (!(d <= c.max_diff)) {
        c.max_diff = std::isnan(d) ? INFINITY : d;
        c.worst_frame = ra.frame, c.worst_node = ra.node, c.worst_component = k;
      }
    }
  }
  c.rows = rows;
  c.ok = c.max_diff <= tolerance * c.scale || (c.scale == 0 && c.max_diff == 0);
  if (!c.ok)
    c.message = cat("displacements differ from the reference by up to ", c.max_diff, " m (frame ", c.worst_frame,
                    ", node ", c.worst_node, ", u", "xyz"[c.worst_component], "), more than tolerance ", tolerance,
                    " x ", c.scale, " m") + identity_note(c.header, who);
  return c;
}

LogComparison compare_logs(const fs::path& produced, const fs::path& reference, double tolerance) {
  return compare_logs(LogFile::at(produced), LogFile::at(reference), tolerance);
}

void copy_as_reference(const LogFile& produced, const ReferenceHeader& header, std::ostream& os,
                       const CompareLimits& limits) {
  LineReader in = open_log(produced, limits, "displacement log");
  os << reference_header_line(header);
  // Line by line: a log this run wrote, but its lines are bounded all the same.
  std::string line;
  while (in.next(line)) os << line << '\n';
}

}  // namespace softcut::app
