#include "mesh/mesher/organs.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "mesh/surface.hpp"

namespace softcut::mesh {

namespace {

using V = Eigen::Vector3d;

// Approximate signed distances, m (negative inside), good enough to blend
// with: exact on the surface, of the right size near it.
double ellipsoid(const V& p, const V& c, const V& r) { return ((p - c).cwiseQuotient(r).norm() - 1) * r.minCoeff(); }
double sphere(const V& p, const V& c, double r) { return (p - c).norm() - r; }
// Smooth union / intersection with a blend of width k (polynomial smooth min).
double smin(double a, double b, double k) {
  const double h = std::max(k - std::abs(a - b), 0.0) / k;
  return std::min(a, b) - h * h * k / 4;
}
double smax(double a, double b, double k) { return -smin(-a, -b, k); }

double liver(const V& p) {
  const double d = smin(ellipsoid(p, {0.025, 0, 0}, {0.075, 0.065, 0.045}),        // right lobe
                  ellipsoid(p, {-0.06, 0.02, 0.012}, {0.06, 0.045, 0.02}), 0.03);  // left lobe
  return smax(d, -(p.z() + 0.022), 0.015);  // flattened underside
}

double kidney(const V& p) {
  V q = p;
  q.y() += 0.006 * (p.x() / 0.055) * (p.x() / 0.055);  // the bean's bend
  const double d = ellipsoid(q, {0, 0, 0}, {0.055, 0.03, 0.024});
  return smax(d, -sphere(q, {0, 0.036, 0}, 0.017), 0.008);  // hilum
}

constexpr double kLigamentLength = 0.035;
double knee_ligament(const V& p) {
  const double t = std::clamp(p.z() / kLigamentLength, 0.0, 1.0), u = 2 * t - 1;
  const double a = 0.005 * (1 + 0.6 * u * u), b = 0.002 * (1 + 0.3 * u * u);  // flare 1.6 to the insertions
  const double th = M_PI / 2 * t, c = std::cos(th), s = std::sin(th);         // 90 degree twist
  const double x = c * p.x() + s * p.y(), y = -s * p.x() + c * p.y();
  const double section = (std::hypot(x / a, y / b) - 1) * b;
  const double slab = std::abs(p.z() - kLigamentLength / 2) - kLigamentLength / 2;
  return smax(section, slab, 0.001);
}

}  // namespace

std::map<std::string, std::vector<int>> organ_landmarks(const std::string& kind, const TetMesh& m,
                                                        const OrganOptions& o) {
  const double s = o.scale;
  const std::vector<int> surface = extract_surface(m).nodes;
  std::map<std::string, std::vector<int>> sets;
  auto add = [&](const char* name, const std::vector<int>& nodes, auto&& keep) {
    std::vector<int>& out = sets[name];
    for (int n : nodes)
      if (keep(V(m.node(n) / s))) out.push_back(n);
  };
  std::vector<int> all(size_t(m.num_nodes()));
  for (int n = 0; n < m.num_nodes(); ++n) all[size_t(n)] = n;
  if (kind == "liver") {
    auto right = [](const V& q) {
      return ellipsoid(q, {0.025, 0, 0}, {0.075, 0.065, 0.045}) <= ellipsoid(q, {-0.06, 0.02, 0.012}, {0.06, 0.045, 0.02});
    };
    add("right_lobe", all, right);
    add("left_lobe", all, [&](const V& q) { return !right(q); });
    add("underside", surface, [](const V& q) { return q.z() <= -0.021; });
    add("dome", surface, [](const V& q) { return (q - V(0.025, 0, 0.045)).norm() <= 0.015; });
    std::vector<char> in_lesion(size_t(m.num_nodes()), 0);
    for (int t = 0; t < m.num_tets(); ++t)
      if (m.labels.size() && m.labels(t) == 2)
        for (int k = 0; k < 4; ++k) in_lesion[size_t(m.tets(t, k))] = 1;
    std::vector<int> lesion;
    for (int n = 0; n < m.num_nodes(); ++n)
      if (in_lesion[size_t(n)]) lesion.push_back(n);
    if (!lesion.empty()) sets["lesion"] = std::move(lesion);
  } else if (kind == "kidney") {
    auto bent = [](const V& p) {
      V q = p;
      q.y() += 0.006 * (p.x() / 0.055) * (p.x() / 0.055);
      return q;
    };
    add("hilum", surface, [&](const V& p) { return sphere(bent(p), {0, 0.036, 0}, 0.017) <= 0.004; });
    add("convex", surface, [&](const V& p) { return bent(p).y() < -0.02 && std::abs(p.x()) < 0.035; });
    add("upper_pole", surface, [](const V& p) { return p.x() > 0.04; });
    add("lower_pole", surface, [](const V& p) { return p.x() < -0.04; });
    add("underside", surface, [](const V& p) { return p.z() < -0.016; });
    add("top", surface, [](const V& p) { return p.z() > 0.016; });
  } else if (kind == "knee_ligament") {
    add("tibial", all, [](const V& p) { return p.z() <= 0.0005; });
    add("femoral", all, [](const V& p) { return p.z() >= kLigamentLength - 0.0005; });
  }
  return sets;
}

const std::vector<std::string>& organ_kinds() {
  static const std::vector<std::string> kinds = {"liver", "kidney", "knee_ligament"};
  return kinds;
}

LabeledShape organ_shape(const std::string& kind, const OrganOptions& o) {
  const std::string name = "generator " + kind;
  if (!(o.scale > 0 && o.scale <= 1e6)) fail(name, ": scale must be in (0, 1000000], got ", o.scale);
  if (!(o.lesion_radius >= 0 && o.lesion_radius <= 0.03)) fail(name, ": lesion_radius must be in [0, 0.03] m, got ", o.lesion_radius);
  const double s = o.scale, lesion = o.lesion_radius;
  const V lesion_at = o.lesion_center;
  if (kind == "liver" && lesion > 0 && !(lesion_at.allFinite() && liver(lesion_at) < -lesion))
    fail(name, ": the lesion (lesion_center, lesion_radius) must lie inside the liver");
  LabeledShape out;
  out.name = name;
  if (kind == "liver") {
    out.bounds = Eigen::AlignedBox3d(V(-0.13, -0.08, -0.035), V(0.11, 0.075, 0.05));
    out.labels = lesion > 0 ? std::vector<int>{1, 2} : std::vector<int>{1};
    out.label = [s, lesion, lesion_at](const V& p) {
      const V q = p / s;
      if (liver(q) >= 0) return 0;
      return sphere(q, lesion_at, lesion) < 0 ? 2 : 1;
    };
  } else if (kind == "kidney") {
    out.bounds = Eigen::AlignedBox3d(V(-0.06, -0.04, -0.03), V(0.06, 0.04, 0.03));
    out.labels = {1, 2};
    out.label = [s](const V& p) {
      const double d = kidney(p / s);
      return d >= 0 ? 0 : d > -0.006 ? 1 : 2;
    };
  } else if (kind == "knee_ligament") {
    out.bounds = Eigen::AlignedBox3d(V(-0.01, -0.01, -0.001), V(0.01, 0.01, kLigamentLength + 0.001));
    out.labels = {1};
    out.label = [s](const V& p) { return knee_ligament(p / s) < 0 ? 1 : 0; };
  } else {
    fail(name, ": unknown organ (use liver, kidney or knee_ligament)");
  }
  out.bounds = Eigen::AlignedBox3d(out.bounds.min() * s, out.bounds.max() * s);
  return out;
}

MesherOptions organ_mesher_options(const LabeledShape& s, const OrganOptions& o) {
  MesherOptions m;
  m.fine_center = o.fine_center;
  m.fine_radius = o.fine_radius;
  m.sliver_bound_deg = o.sliver_bound_deg;
  m.seed = o.seed;
  if (o.fine_radius != 0 && !(o.fine_ratio > 0.05 && o.fine_ratio <= 1))
    fail(s.name, ": fine_ratio must be in (0.05, 1], got ", o.fine_ratio);
  const auto set_size = [&](double h) { m.cell_size = h, m.fine_size = o.fine_ratio * h; };
  if (o.target_tets > 0) {
    if (o.cell_size != 0) fail(s.name, ": give target_tets or cell_size, not both");
    // The estimate scales as h^-3 when cell and fine sizes scale together.
    set_size(s.bounds.sizes().maxCoeff() / 10);
    set_size(m.cell_size * std::cbrt(estimate_tets(s, m) / o.target_tets));
  } else {
    set_size(o.cell_size);
  }
  return m;
}

std::string over_limit(double tets, const MeshLimit& limit) {
  const auto count = [](double n) {
    char buf[32];
    std::snprintf(buf, sizeof buf, n < 1e15 ? "%.0f" : "%.3g", n);  // llround(inf) was -9223372036854775808
    return std::string(buf);
  };
  return cat("about ", std::isfinite(tets) ? count(tets) : std::string("infinitely many"), " tetrahedra, over this run's limit of ",
             count(limit.max_tets), "; ask for fewer (", limit.raise, ")");
}

TetMesh mesh_to_target(const LabeledShape& shape, const OrganOptions& o, const MeshLimit& limit, const Mesher& mesh,
                       MesherReport* report) {
  MesherOptions m = organ_mesher_options(shape, o);
  m.max_vertices = max_vertices_for(limit.max_tets);
  m.stop = limit.stop;
  const auto refuse = [&](double tets) {
    if (!(tets <= limit.max_tets)) fail(shape.name, ": ", over_limit(tets, limit));
  };
  const double estimate = estimate_tets(shape, m);
  refuse(estimate);
  TetMesh out = mesh(m, report);
  if (o.target_tets > 0 && std::abs(out.num_tets() - o.target_tets) > 0.2 * o.target_tets) {
    const double f = std::cbrt(double(out.num_tets()) / o.target_tets);
    m.cell_size *= f, m.fine_size *= f;
    refuse(estimate_tets(shape, m) * out.num_tets() / estimate);  // the first mesh calibrates the estimate
    out = mesh(m, report);
  }
  refuse(out.num_tets());
  return out;
}

TetMesh generate_organ(const std::string& kind, const OrganOptions& o, const MeshLimit& limit, MesherReport* report) {
  const LabeledShape shape = organ_shape(kind, o);
  return mesh_to_target(shape, o, limit, [&](const MesherOptions& m, MesherReport* r) { return mesh_shape(shape, m, r); },
                        report);
}

}  // namespace softcut::mesh
