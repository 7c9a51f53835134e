#include "app/mesh_limits.hpp"

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <limits>
#include <sstream>

#include "core/error.hpp"

namespace softcut::app {

namespace {

bool parse_number(const std::string& s, double& v) {
  char* end = nullptr;
  v = std::strtod(s.c_str(), &end);
  return !s.empty() && end == s.c_str() + s.size() && std::isfinite(v);
}

}  // namespace

bool parse_vec3(const std::string& text, double out[3]) {
  std::stringstream ss(text);
  std::string part;
  int n = 0;
  while (std::getline(ss, part, ',')) {
    if (n == 3 || !parse_number(part, out[n])) return false;
    ++n;
  }
  return n == 3 && text.back() != ',';
}

CLI::Validator vec3_text() {
  return CLI::Validator(
      [](std::string& s) {
        double v[3];
        return parse_vec3(s, v) ? std::string() : "expected 3 comma-separated numbers X,Y,Z, got '" + s + "'";
      },
      "");
}

CLI::Validator number_text() {
  return CLI::Validator(
      [](std::string& s) {
        double v;
        return parse_number(s, v) ? std::string() : "expected a number, got '" + s + "'";
      },
      "");
}

void MeshLimits::declare(CLI::App& app, bool tets) {
  app.add_option("--timeout", timeout_s, "wall-clock limit in seconds (default 3600; 0: none); past it the command "
                 "stops and exits 124")
      ->check(plain(CLI::NonNegativeNumber))->type_name("S");
  app.add_option("--max-memory", max_memory, "bytes a file and what it decodes to may take (default 2G; K/M/G "
                 "suffix; 0: none)")
      ->transform(plain(CLI::AsSizeValue(false)))->type_name("BYTES");
  if (tets)
    app.add_option("--max-tets", max_tets, "largest mesh to make, refused before meshing (default 2000000)")
        ->check(plain(CLI::Range(1, 2147483647)))->type_name("N");
}

std::size_t MeshLimits::read_bytes() const {
  return max_memory == 0 ? std::numeric_limits<std::size_t>::max() : std::size_t(max_memory / 4);
}

std::size_t MeshLimits::volume_bytes() const {
  return max_memory == 0 ? std::numeric_limits<std::size_t>::max() : std::size_t(max_memory / 2);
}

mesh::ReadOptions MeshLimits::read() const {
  mesh::ReadOptions r;
  r.max_bytes = read_bytes();
  return r;
}

std::unique_ptr<Watchdog> MeshLimits::start(const std::string& command) const {
  // Meshing polls the flag (between Mesh_3's insertions, per slice of
  // softcut's seeding grid); reading and voxel work do not: the watchdog
  // ends those after a grace of a quarter of the limit (2-30 s).
  const double grace = std::clamp(0.25 * timeout_s, 2.0, 30.0);
  return std::make_unique<Watchdog>(timeout_s, grace,
                                    cat(command, ": the wall-clock limit of ", timeout_s, " s (--timeout) was reached"));
}

}  // namespace softcut::app
