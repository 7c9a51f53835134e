#include "app/reference_log.hpp"

#include <algorithm>
#include <cmath>
#include <fstream>
#include <sstream>
#include <vector>

#include "core/error.hpp"

namespace fs = std::filesystem;

namespace softcut::app {

namespace {

struct Row {
  long frame = 0, node = 0;
  double u[3] = {0, 0, 0};
};

std::vector<Row> read_log(const fs::path& path) {
  std::ifstream in(path);
  if (!in) fail(path.string(), ": cannot open the displacement log");
  std::vector<Row> rows;
  std::string line;
  int lineno = 0;
  while (std::getline(in, line)) {
    ++lineno;
    if (line.empty() || line[0] == '#' || line.rfind("frame", 0) == 0) continue;
    std::replace(line.begin(), line.end(), ',', ' ');
    std::istringstream ss(line);
    Row r;
    double time = 0;
    if (!(ss >> r.frame >> time >> r.node >> r.u[0] >> r.u[1] >> r.u[2]))
      fail(path.string(), ":", lineno, ": expected frame,time,node,ux,uy,uz");
    rows.push_back(r);
  }
  return rows;
}

}  // namespace

fs::path reference_path(const fs::path& scenario) {
  return scenario.parent_path() / (scenario.stem().string() + ".ref.csv");
}

LogComparison compare_logs(const fs::path& produced, const fs::path& reference, double tolerance) {
  const std::vector<Row> a = read_log(produced), b = read_log(reference);
  LogComparison c;
  if (a.size() != b.size()) {
    c.stale = true;
    c.message = cat("the log has ", a.size(), " rows, the reference ", b.size(), " (frames or logged nodes changed)");
    return c;
  }
  for (size_t i = 0; i < a.size(); ++i) {
    if (a[i].frame != b[i].frame || a[i].node != b[i].node) {
      c.stale = true;
      c.message = cat("row ", i + 2, " is frame ", a[i].frame, " node ", a[i].node, ", the reference has frame ", b[i].frame,
                      " node ", b[i].node);
      return c;
    }
    for (int k = 0; k < 3; ++k) {
      c.scale = std::max(c.scale, std::abs(b[i].u[k]));
      const double d = std::abs(a[i].u[k] - b[i].u[k]);
      if (!(d <= c.max_diff)) {
        c.max_diff = std::isnan(d) ? INFINITY : d;
        c.worst_frame = a[i].frame, c.worst_node = a[i].node, c.worst_component = k;
      }
    }
  }
  c.ok = c.max_diff <= tolerance * c.scale || (c.scale == 0 && c.max_diff == 0);
  if (!c.ok)
    c.message = cat("displacements differ from the reference by up to ", c.max_diff, " m (frame ", c.worst_frame,
                    ", node ", c.worst_node, ", u", "xyz"[c.worst_component], "), more than tolerance ", tolerance,
                    " x ", c.scale, " m");
  return c;
}

}  // namespace softcut::app
