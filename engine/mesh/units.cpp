#include "mesh/units.hpp"

#include <cmath>
#include <cstdio>

#include "core/warning.hpp"

namespace softcut::mesh {

namespace {

struct Unit {
  const char* name;
  double metres;
};
constexpr Unit kUnits[] = {{"m", 1}, {"cm", 1e-2}, {"mm", 1e-3}, {"um", 1e-6}};

// "190 m", "0.25 mm": a length for messages, in the unit that reads best.
std::string length_text(double metres) {
  char buf[64];
  if (metres >= 0.1) std::snprintf(buf, sizeof buf, "%.3g m", metres);
  else if (metres >= 1e-4) std::snprintf(buf, sizeof buf, "%.3g mm", metres * 1e3);
  else std::snprintf(buf, sizeof buf, "%.3g um", metres * 1e6);
  return buf;
}

}  // namespace

const char* known_units() { return "m, cm, mm or um"; }

double unit_metres(const std::string& unit, const std::string& what) {
  for (const Unit& u : kUnits)
    if (unit == u.name) return u.metres;
  fail(what, ": unknown unit '", unit, "' (use ", known_units(), ")");
}

std::string guess_unit(double largest_side, const std::string& what) {
  if (!(largest_side > 0) || !std::isfinite(largest_side))
    fail(what, ": cannot guess the unit of a body of size ", largest_side, "; give it (", known_units(), ")");
  if (largest_side <= 1) {
    if (largest_side < kPlausibleMinSize)
      fail(what, ": the body is ", largest_side, " units across, too small for an organ in any unit softcut knows; "
           "give the unit (", known_units(), ") and a scale");
    return "m";
  }
  if (largest_side <= 1e3) return "mm";
  if (largest_side <= 1e6) return "um";
  fail(what, ": the body is ", largest_side, " units across, too large for an organ in any unit softcut knows; "
       "give the unit (", known_units(), ") and a scale");
}

bool check_plausible_size(const Eigen::AlignedBox3d& box, const std::string& what, Diagnostics& diag) {
  if (box.isEmpty()) return false;
  const double side = box.sizes().maxCoeff();
  if (!std::isfinite(side) || (side >= kPlausibleMinSize && side <= kPlausibleMaxSize)) return false;
  const Eigen::Vector3d s = box.sizes();
  char dims[128];
  std::snprintf(dims, sizeof dims, "%.3g x %.3g x %.3g m", s.x(), s.y(), s.z());
  std::string advice;
  if (side > kPlausibleMaxSize && side <= 1e3 * kPlausibleMaxSize)
    advice = cat("if the file is in millimetres, give its unit: s:mesh{ file = ..., unit = \"mm\" } or "
                 "softcut mesh convert --unit mm IN OUT (", length_text(side * 1e-3), " across then)");
  else if (side > kPlausibleMaxSize)
    advice = cat("if the file is in micrometres, give its unit: unit = \"um\" (", length_text(side * 1e-6),
                 " across then); otherwise scale it (s:mesh{ scale = ... }, softcut mesh convert --scale)");
  else if (side >= kPlausibleMinSize * 1e-3)
    advice = cat("if the file is in metres but was scaled as millimetres, drop unit = \"mm\" or scale it by 1000 "
                 "(", length_text(side * 1e3), " across then)");
  else
    advice = "scale it (s:mesh{ scale = ... }, softcut mesh convert --scale S)";
  warn_coded(diag, "implausible_size", what, ": the body is ", length_text(side), " across (bounding box ", dims,
                  "), outside the 1 mm to 1 m of organs; lengths are in metres: ", advice);
  return true;
}

Eigen::AlignedBox3d bounding_box(const TetMesh& m) {
  Eigen::AlignedBox3d box;
  for (int n = 0; n < m.num_nodes(); ++n) box.extend(m.node(n));
  return box;
}

void scale_nodes(TetMesh& m, double factor, const std::string& what) {
  if (!(factor > 0) || !std::isfinite(factor)) fail(what, ": the scale must be a positive number, got ", factor);
  if (factor == 1) return;
  m.nodes *= factor;
  if (!m.nodes.allFinite()) fail(what, ": scaling by ", factor, " leaves coordinates that are not finite numbers");
}

}  // namespace softcut::mesh
